#pragma once
// The stackers of config/sites/plant.yaml on maps/plant.yaml, as the stacker tests build them.

#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "orders/loader_desk.hpp"
#include "robot/robot_factory.hpp"
#include "robot/stacker/stacker.hpp"
#include "test_paths.hpp"

namespace fleet::test {

struct PlantStacker {
  std::shared_ptr<const map::SiteMap> site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  std::map<int, geometry::Pose2> loads;
  std::map<std::string, int> load_at;

  PlantStacker() {
    int id = 1;
    for (const auto& area : site->site.loading_areas) {
      if (!area.pallet_at_start) continue;
      loads[id] = area.pose;
      load_at[area.id] = id++;
    }
  }

  /// The stacker of config/sites/plant.yaml's `stackers` fleet, as the agent builds it. Without
  /// `traffic` no traffic manager grants here, so traffic control is off (the lanes stay one-way).
  std::unique_ptr<robot::Stacker> make(const std::string& home_id, bool traffic = false) const {
    config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
    config.settings.set("traffic.enabled", traffic ? "true" : "false", "stacker_test");
    const auto* fleet =
        &*std::find_if(config.fleets.begin(), config.fleets.end(), [](const auto& f) { return f.id == "stackers"; });
    std::unique_ptr<robot::Robot> made =
        robot::make_robot(*fleet, config, site, site->site.find_home(home_id)->pose, 3, 1);
    auto* stacker = dynamic_cast<robot::Stacker*>(made.get());
    if (stacker == nullptr) throw std::logic_error("the stackers fleet does not build a Stacker");
    made.release();
    return std::unique_ptr<robot::Stacker>(stacker);
  }

  task::TaskOrder transport(const std::string& from, const std::string& to) const {
    task::TaskOrder o;
    o.order_id = "7";
    o.pick_area_id = from;
    o.pick_area = site->site.find_area(from)->pose;
    o.drop_area_id = to;
    o.drop_area = site->site.find_area(to)->pose;
    return o;
  }

  /// Where a loader's transporter stands behind the picker picking at rack place `place`: the
  /// picker 1 m out, side-on, the place on its left; the stacker's pallet centre (0.35 m behind
  /// its body's: forks 1.15 m, pallet 1.2 m) 1.0 m behind the picker's centre, so the pallet's near
  /// edge stands 7.5 cm behind the 0.65 m base, its first row where the arm reaches (0.55 m behind
  /// the base's centre).
  geometry::Pose2 behind_picker_at(const std::string& place) const {
    const orders::LoaderLayout layout;
    const geometry::Pose2 picker = orders::picker_stop_pose(site->site.find_area(place)->pose, layout.item_standoff);
    return orders::transporter_pose(picker, layout.deck_x, layout.pallet_x);
  }
};

}  // namespace fleet::test
