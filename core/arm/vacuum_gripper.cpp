#include "arm/vacuum_gripper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace fleet::arm {

namespace {

constexpr double kPascalPerBar = 1e5;

void require_positive(double value, const char* name) {
  if (!(value > 0.0)) {
    throw std::invalid_argument(std::string("VacuumGripperConfig.") + name + " must be > 0, got " +
                                std::to_string(value));
  }
}

template <typename... Values>
std::string format(const char* pattern, Values... values) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

}  // namespace

VacuumGripper::VacuumGripper(VacuumGripperConfig config) : config_(config) {
  if (config_.cup_count < 1) {
    throw std::invalid_argument("VacuumGripperConfig.cup_count must be >= 1, got " + std::to_string(config_.cup_count));
  }
  require_positive(config_.cup_diameter, "cup_diameter");
  require_positive(config_.plate_length, "plate_length");
  require_positive(config_.plate_width, "plate_width");
  require_positive(config_.gravity, "gravity");
  require_positive(config_.friction, "friction");
  require_positive(config_.safety_factor, "safety_factor");
  require_positive(config_.atmospheric, "atmospheric");
  require_positive(config_.max_mass, "max_mass");
  require_positive(config_.min_side, "min_side");
  require_positive(config_.max_side, "max_side");
  if (config_.acceleration < 0.0) {
    throw std::invalid_argument("VacuumGripperConfig.acceleration must be >= 0, got " +
                                std::to_string(config_.acceleration));
  }
  if (config_.min_side > config_.max_side) {
    throw std::invalid_argument("VacuumGripperConfig.min_side " + std::to_string(config_.min_side) +
                                " exceeds max_side " + std::to_string(config_.max_side));
  }
  if (config_.source_vacuum) require_positive(*config_.source_vacuum, "source_vacuum");
}

double VacuumGripper::cup_area() const {
  const double radius = config_.cup_diameter / 2.0;
  return std::numbers::pi * radius * radius;
}

GripForces VacuumGripper::forces(double mass) const {
  const VacuumGripperConfig& c = config_;
  GripForces f;
  // [Picker thesis, eq. 3.10]: lifting straight up, the cups carry the weight and the inertia.
  f.lift = mass * (c.gravity + c.acceleration) * c.safety_factor;
  // [Picker thesis, eq. 3.12]: moving sideways, the inertia is taken by friction at the lips, so
  // it counts 1/μ times.
  f.hold = mass * (c.gravity + c.acceleration / c.friction) * c.safety_factor;
  // [Picker thesis, eq. 3.14]: the thesis divides the holding force; the larger of the two is the
  // one to meet, and is the holding force whenever μ <= 1.
  f.per_cup = std::max(f.lift, f.hold) / c.cup_count;
  // [Picker thesis, eq. 3.15]: P = F / A, in bar below atmospheric.
  f.vacuum = f.per_cup / cup_area() / kPascalPerBar;
  // [Picker thesis, eq. 3.16]: the absolute pressure the source must pull the cups down to.
  f.absolute_pressure = c.atmospheric - f.vacuum;
  return f;
}

double VacuumGripper::source_vacuum() const {
  return config_.source_vacuum.value_or(forces(config_.max_mass).vacuum);
}

bool VacuumGripper::covers(const Box& box, double plate_yaw_on_face, double along_length, double along_width) const {
  // A rectangle lies in a rectangle when its bounding box does.
  const double cos_yaw = std::abs(std::cos(plate_yaw_on_face));
  const double sin_yaw = std::abs(std::sin(plate_yaw_on_face));
  const double half_length = 0.5 * (config_.plate_length * cos_yaw + config_.plate_width * sin_yaw);
  const double half_width = 0.5 * (config_.plate_length * sin_yaw + config_.plate_width * cos_yaw);
  return std::abs(along_length) + half_length <= 0.5 * box.length + 1e-12 &&
         std::abs(along_width) + half_width <= 0.5 * box.width + 1e-12;
}

GripCheck VacuumGripper::can_hold(const Box& box, double plate_yaw_on_face) const {
  const VacuumGripperConfig& c = config_;
  GripCheck check;
  check.forces = forces(box.mass);
  if (!(box.mass > 0.0)) {
    check.reason = format("box mass %.2f kg is not positive", box.mass);
    return check;
  }
  if (box.mass > c.max_mass) {
    check.reason = format("box of %.2f kg exceeds the %.2f kg payload", box.mass, c.max_mass);
    return check;
  }
  for (const double side : {box.length, box.width, box.height}) {
    if (side < c.min_side || side > c.max_side) {
      check.reason = format("box side %.3f m outside the handled range [%.2f m, %.2f m]", side, c.min_side, c.max_side);
      return check;
    }
  }
  if (!covers(box, plate_yaw_on_face)) {
    const double cos_yaw = std::abs(std::cos(plate_yaw_on_face));
    const double sin_yaw = std::abs(std::sin(plate_yaw_on_face));
    check.reason =
        format("top face %.3f x %.3f m does not cover the cups (%.3f x %.3f m as turned)", box.length, box.width,
               c.plate_length * cos_yaw + c.plate_width * sin_yaw, c.plate_length * sin_yaw + c.plate_width * cos_yaw);
    return check;
  }
  const double available = source_vacuum();
  if (check.forces.vacuum > available * (1.0 + 1e-9)) {
    check.reason = format("needs %.3f bar of vacuum, the source holds %.3f bar", check.forces.vacuum, available);
    return check;
  }
  check.ok = true;
  return check;
}

}  // namespace fleet::arm
