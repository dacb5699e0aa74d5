#pragma once

#include <optional>
#include <string>

namespace fleet::arm {

/// A box to pick, gripped on its top face (length x width); kept upright [Picker thesis, section 3.2.4].
struct Box {
  double mass = 0.0;    ///< kg
  double length = 0.0;  ///< m, top face
  double width = 0.0;   ///< m, top face
  double height = 0.0;  ///< m
};

/// The custom vacuum gripper [Picker thesis, sections 3.2.5-3.3.4]: four 40 mm suction cups on a
/// 12 x 8 cm plate, sized by the force calculations of eq. 3.10-3.16.
struct VacuumGripperConfig {
  int cup_count = 4;
  double cup_diameter = 0.040;  ///< m
  /// Outline of the cups' lips on the plate; the gripped face must cover it or the outer cups leak.
  double plate_length = 0.12;  ///< m
  double plate_width = 0.08;   ///< m
  double gravity = 9.81;       ///< m/s² [Picker thesis, eq. 3.10]
  /// Acceleration of the system while carrying a box. The thesis does not state it; its 103.1 N
  /// for 5 kg at s = 2 [Picker thesis, eq. 3.11] gives 0.5 m/s². Motions that carry a box respect it.
  double acceleration = 0.5;   ///< m/s²
  double friction = 0.5;       ///< μ between cup and box [Picker thesis, eq. 3.12]
  double safety_factor = 2.0;  ///< s, "2.0 for grabbing from the top" [Picker thesis, section 3.3.3]
  double atmospheric = 1.013;  ///< bar [Picker thesis, eq. 3.16]
  double max_mass = 5.0;       ///< kg: the UR5's payload, the thesis's box limit [Picker thesis, section 3.2.5]
  double min_side = 0.10;      ///< m: smallest box of the product analysis [Picker thesis, section 3.2.5]
  double max_side = 0.40;      ///< m: largest box picked in the experiments [Picker thesis, section 3.2.5]
  /// Vacuum the source holds at the cups, bar below atmospheric. Empty: the source is sized for the
  /// design case (a box of max_mass), as in [Picker thesis, section 3.3.4]; the thesis names no pump rating.
  std::optional<double> source_vacuum;
};

/// The forces and pressures of eq. 3.10-3.16 for one box.
struct GripForces {
  double lift = 0.0;               ///< N, m(g + a)s [Picker thesis, eq. 3.10]
  double hold = 0.0;               ///< N, m(g + a/μ)s [Picker thesis, eq. 3.12]
  double per_cup = 0.0;            ///< N, the larger of the two shared by the cups [Picker thesis, eq. 3.14]
  double vacuum = 0.0;             ///< bar below atmospheric, per_cup / cup area [Picker thesis, eq. 3.15]
  double absolute_pressure = 0.0;  ///< bar, atmospheric - vacuum [Picker thesis, eq. 3.16]
};

/// Whether a box can be lifted and held, and if not why.
struct GripCheck {
  bool ok = false;
  std::string reason;  ///< empty when ok
  GripForces forces;
};

class VacuumGripper {
 public:
  /// Throws std::invalid_argument naming the field for a non-positive count, size, friction,
  /// safety factor or mass, or min_side > max_side.
  explicit VacuumGripper(VacuumGripperConfig config = {});

  const VacuumGripperConfig& config() const { return config_; }

  double cup_area() const;  ///< m², one cup
  GripForces forces(double mass) const;
  /// Vacuum the source holds (configured, or that of the design case).
  double source_vacuum() const;

  /// Whether `box` can be lifted and held: its mass within the payload, every side within
  /// [min_side, max_side], its top face covering the cups' outline with the plate turned by
  /// `plate_yaw_on_face` (rad) from the face's length, and the source's vacuum at least the one
  /// eq. 3.15 asks for.
  GripCheck can_hold(const Box& box, double plate_yaw_on_face = 0.0) const;
  /// Whether the cups' outline, turned by `plate_yaw_on_face` from the face's length and its centre off the
  /// face's centre by `along_length`, `along_width` (m, in the face's axes), lies on the top face: where a
  /// plate set down on a box located with an error still grips it.
  bool covers(const Box& box, double plate_yaw_on_face, double along_length = 0.0, double along_width = 0.0) const;

 private:
  VacuumGripperConfig config_;
};

}  // namespace fleet::arm
