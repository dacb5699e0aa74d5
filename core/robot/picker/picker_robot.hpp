#pragma once

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "robot/forklift/forklift.hpp"
#include "robot/picker/picker_arm_work.hpp"

namespace fleet::robot {

/// The picker's settings: its base runs the forklift software without forks, its arm
/// (PickerArmStops) works at the stops of a pick tour.
struct PickerConfig {
  ForkliftConfig base;
  perception::DepthMarkerCameraParams box_camera;  ///< the boom camera that reads the boxes' markers
  PickerArmLayout arm_layout;
};

/// The picker's software as make_robot configures it for `fleet` (robot_type picker): the
/// forklift software without forks on the Summit-XLS, with the UR5 arm and its boom camera
/// [Picker thesis]. For whoever needs the picker's parts without the robot (pick-eval).
PickerConfig picker_robot_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                 const map::SiteMap& site);

}  // namespace fleet::robot
