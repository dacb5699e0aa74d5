// The picker's software as the agent builds it (its half of the type table,
// core/robot/robot_types.def).
#include "robot/picker/picker_robot.hpp"

#include "robot/forklift/forklift_robot.hpp"
#include "robot/picker/picker_arm_stops.hpp"
#include "sim/summit_xls.hpp"

namespace fleet::robot {

/// The picker's base [Picker thesis]: the forklift software without forks on the Summit-XLS, localised by the
/// site's markers and wheel odometry.
PickerConfig picker_robot_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                 const map::SiteMap& site) {
  PickerConfig p;
  ForkliftConfig& c = p.base;
  c = forklift_robot_config(config, fleet, site);
  c.type_name = "picker";
  c.forks = false;
  // The boom camera over the left side, where the pallet stands at a stop.
  p.box_camera.mount = {0.25, 0.20, 1.50};
  const geometry::Footprint footprint = c.sim.forklift.footprint;
  c.sim.forklift = sim::summit_xls_body_params();
  c.sim.forklift.footprint = footprint;
  c.sim.marker_localization = true;
  return p;
}

std::unique_ptr<Robot> make_picker(const RobotBuild& build) {
  const PickerConfig config = picker_robot_config(build.config, build.fleet, *build.site);
  const std::uint64_t seed = build.seed ^ (build.stream * 0x9e3779b97f4a7c15ULL) ^ 0xa7b0ULL;
  PickerArmLayout deck_layout = config.arm_layout;
  deck_layout.tray = deck_layout.deck;
  deck_layout.tray_layers = deck_layout.deck_layers;
  auto arm = std::make_unique<PickerArmStops>(make_picker_arm_work(config.box_camera, config.arm_layout, seed),
                                              make_picker_arm_work(config.box_camera, deck_layout, seed ^ 0xdec0ULL));
  return std::make_unique<Forklift>(config.base, build.site, build.home, build.seed, build.stream, std::move(arm));
}

}  // namespace fleet::robot
