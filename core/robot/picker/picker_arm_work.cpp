#include "robot/picker/picker_arm_work.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace fleet::robot {

arm::Box box_of(const map::BoxStock& stock) {
  return {stock.mass, stock.length, stock.width, stock.height};
}

namespace {

/// Locating a box: the camera's frames until it reads the marker, at most `limit` s. The thesis's
/// localization scans take about 5 s per camera rotation and 5 s to extract [Picker thesis, section 5.3.3.1.3].
bool locate(perception::DepthMarkerCamera& camera, const perception::BoxMarker& marker, double& t, double limit,
            perception::BoxSighting& seen) {
  camera.look_at(marker.top_centre);
  const double start = t;
  const std::vector<perception::BoxMarker> one{marker};
  for (; t - start < limit; t += 1.0 / camera.params().rate_hz) {
    if (!camera.frame_due(t)) continue;
    for (const auto& s : camera.capture(t, {}, one)) {
      if (s.id == marker.id) {
        seen = s;
        return true;
      }
    }
  }
  return false;
}

}  // namespace

PickerArmWork::PickerArmWork(arm::PickMotionPlanner planner, perception::DepthMarkerCameraParams camera,
                             PickerArmLayout layout, std::uint64_t seed)
    : planner_(std::move(planner)), camera_(camera, seed), layout_(layout) {}

perception::BoxMarker PickerArmWork::marker_at(const map::BoxStock& stock, int k, int layer) const {
  const int slot = k % layout_.slots;
  const double x = layout_.slot_pitch * ((slot + 1) / 2) * (slot % 2 == 1 ? 1.0 : -1.0);
  const double y = layout_.pallet_edge_y + stock.width / 2.0;
  const double z = layout_.pallet_top + (layer + 1) * stock.height;
  return {k + 1, {x, y, z}, 0.0};
}

std::vector<Eigen::Vector2d> PickerArmWork::base_moves(double box_x) const {
  // Where it stands first; then the box slid in front of the arm; then that and a step away from
  // the pallet, for a box too low to reach close by (the elbow keeps 60 degrees [Picker thesis, Table 10]).
  std::vector<Eigen::Vector2d> moves{{0.0, 0.0}};
  for (double away : {0.0, 0.05, 0.10}) {
    if (std::abs(box_x) > 1e-9 || away > 0.0) moves.push_back({box_x, away});
  }
  return moves;
}

std::string PickerArmWork::tray_refusal(int quantity, const std::vector<map::BoxStock>& tray) const {
  const std::size_t holds = layout_.tray.size() * static_cast<std::size_t>(std::max(layout_.tray_layers, 1));
  if (tray.size() + static_cast<std::size_t>(quantity) <= holds) return {};
  return "the tray holds " + std::to_string(holds) + " boxes, " + std::to_string(tray.size()) + " on it, " +
         std::to_string(quantity) + " more asked for";
}

Eigen::Vector3d PickerArmWork::tray_bottom(const std::vector<map::BoxStock>& tray, std::size_t index) const {
  const std::size_t slots = layout_.tray.size();
  Eigen::Vector3d bottom = layout_.tray.at(index % slots);
  for (std::size_t below = index % slots; below < index && below < tray.size(); below += slots) {
    bottom.z() += tray[below].height;
  }
  return bottom;
}

bool PickerArmWork::pick_box(const map::BoxStock& stock, const perception::BoxMarker& truth,
                             std::vector<map::BoxStock>& tray, double& t, ArmWork& work) {
  constexpr double kLocateLimit = 10.0;  // s: one scan and one extraction [Picker thesis, section 5.3.3.1.3]
  const std::string which = "box " + std::to_string(work.boxes + 1) + " of " + stock.item;
  arm::MotionPlan picked;
  picked.reason = "its marker was not read within " + std::to_string(static_cast<int>(kLocateLimit)) + " s";
  Eigen::Vector2d at{0.0, 0.0};
  for (const Eigen::Vector2d& move : base_moves(truth.top_centre.x())) {
    // The base moves (the arm asks navigation to [Picker thesis, section 5.3.3.1.2]) and looks again.
    work.duration += (move - at).norm() / layout_.slide_speed;
    at = move;
    perception::BoxMarker seen_from_here = truth;
    seen_from_here.top_centre.x() -= move.x();
    seen_from_here.top_centre.y() += move.y();
    perception::BoxSighting seen;
    const double before = t;
    const bool found = locate(camera_, seen_from_here, t, kLocateLimit, seen);
    work.duration += t - before;  // a marker not read costs the whole scan
    if (!found) continue;
    picked = planner_.plan_pick({box_of(stock), seen.top_centre, seen.yaw});
    if (picked.ok) break;
  }
  if (!picked.ok) {
    work.reason = which + ": " + picked.reason;
    return false;
  }
  work.duration += at.norm() / layout_.slide_speed;  // back beside the pallet's middle
  const arm::MotionPlan stowed =
      planner_.plan_drop(box_of(stock), {tray_bottom(tray, tray.size()), 0.0}, picked.plate_yaw_on_box);
  if (!stowed.ok) {
    work.reason = which + " onto the tray: " + stowed.reason;
    return false;
  }
  work.duration += picked.duration() + stowed.duration();
  t += picked.duration() + stowed.duration();
  tray.push_back(stock);
  ++work.boxes;
  return true;
}

ArmWork PickerArmWork::pick(const map::BoxStock& stock, int quantity, std::vector<map::BoxStock>& tray) {
  ArmWork work;
  work.reason = tray_refusal(quantity, tray);
  if (!work.reason.empty()) return work;
  for (int k = 0; k < quantity; ++k) {
    if (!pick_box(stock, marker_at(stock, k, 0), tray, camera_time_, work)) return work;
  }
  work.ok = true;
  return work;
}

ArmWork PickerArmWork::pick_at(const map::BoxStock& stock, int position, int layer, std::vector<map::BoxStock>& tray) {
  ArmWork work;
  work.reason = tray_refusal(1, tray);
  if (!work.reason.empty()) return work;
  work.ok = pick_box(stock, marker_at(stock, position, layer), tray, camera_time_, work);
  return work;
}

ArmWork PickerArmWork::drop(const std::vector<map::BoxStock>& tray, int on_pallet) {
  ArmWork work;
  for (std::size_t i = tray.size(); i-- > 0;) {
    const map::BoxStock& stock = tray[i];
    const std::string which = "box " + std::to_string(i + 1) + " of " + stock.item;
    const Eigen::Vector3d top = tray_bottom(tray, i) + Eigen::Vector3d(0.0, 0.0, stock.height);
    const arm::MotionPlan taken = planner_.plan_pick({box_of(stock), top, 0.0});
    if (!taken.ok) {
      work.reason = which + " off the tray: " + taken.reason;
      return work;
    }
    const int placed = on_pallet + work.boxes;
    const perception::BoxMarker spot = marker_at(stock, placed, placed / layout_.slots);
    arm::MotionPlan dropped;
    Eigen::Vector2d at{0.0, 0.0};
    for (const Eigen::Vector2d& move : base_moves(spot.top_centre.x())) {
      work.duration += (move - at).norm() / layout_.slide_speed;
      at = move;
      const Eigen::Vector3d put{spot.top_centre.x() - move.x(), spot.top_centre.y() + move.y(),
                                spot.top_centre.z() - stock.height};
      dropped = planner_.plan_drop(box_of(stock), {put, 0.0}, taken.plate_yaw_on_box);
      if (dropped.ok) break;
    }
    if (!dropped.ok) {
      work.reason = which + " onto the pallet: " + dropped.reason;
      return work;
    }
    work.duration += at.norm() / layout_.slide_speed + taken.duration() + dropped.duration();
    ++work.boxes;
  }
  work.ok = true;
  return work;
}

PickerArmWork make_picker_arm_work(const perception::DepthMarkerCameraParams& camera, const PickerArmLayout& layout,
                                   std::uint64_t seed) {
  return PickerArmWork(arm::PickMotionPlanner(arm::Ur5{}, arm::VacuumGripper{}), camera, layout, seed);
}

}  // namespace fleet::robot
