// The cart's software as the agent builds it (its half of the type table,
// core/robot/robot_types.def).
#include "robot/forklift/forklift_robot.hpp"

namespace fleet::robot {

/// The forklift software without forks: route planning, traffic, the look ahead and the safety
/// stop as every wheeled robot of Fleet has them. Its path follower commands a forward speed and
/// a yaw rate only [Forklift thesis, eq. 6.2], so on the simulated wheel base (the mecanum model
/// with no sideways command) it drives as a differential base does. Localised by UWB where the
/// site has anchors, by the site's markers and wheel odometry where it has none.
std::unique_ptr<Robot> make_cart(const RobotBuild& build) {
  ForkliftConfig c = forklift_robot_config(build.config, build.fleet, *build.site);
  c.type_name = "cart";
  c.forks = false;
  c.sim.marker_localization = build.site->site.uwb_anchors.empty();
  return std::make_unique<Forklift>(c, build.site, build.home, build.seed, build.stream);
}

}  // namespace fleet::robot
