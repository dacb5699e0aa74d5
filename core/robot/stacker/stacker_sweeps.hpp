#pragma once
// What a stacker's manoeuvres sweep off its route: docking, the way out of a dock or bay, moving
// up straight back. Traffic holds these areas for it (TrafficRoute::work_area, arrival_area) so
// nobody is granted into them while it manoeuvres.

#include <vector>

#include "control/docking_law.hpp"
#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"

namespace fleet::robot {

struct StackerConfig;

/// The unit vector along heading `yaw`.
geometry::Vec2 heading_of(double yaw);
/// The rear axle's pose (the control reference) when the body's centre stands at `centre`.
geometry::Pose2 rear_axle_at(const geometry::Pose2& centre, const sim::TricycleGeometry& geometry);

/// Where the docked pallet's centre lies ahead of the rear axle: the fork tips are at the pocket
/// depth beyond the entry face.
double carried_offset(const control::DockingParams& docking, const sim::TricycleGeometry& geometry);

/// `corners` with their mirror image across the line through `axis` along its heading. Docked on
/// that line, a stacker turns out onto the lane to either side: over the area it docked by or over
/// its mirror image.
std::vector<geometry::Vec2> with_mirror_image(std::vector<geometry::Vec2> corners, const geometry::Pose2& axis);

class StackerSweeps {
 public:
  /// `config` must outlive it.
  explicit StackerSweeps(const StackerConfig& config);
  StackerSweeps(const StackerSweeps&) = delete;
  StackerSweeps& operator=(const StackerSweeps&) = delete;

  /// Adds the corners of the footprint with its rear axle at `rear` heading `yaw`, grown by the
  /// work-area margin: one body of a swept area.
  void add_body(std::vector<geometry::Vec2>& corners, geometry::Vec2 rear, double yaw) const;
  /// The corners of the footprints the docking manoeuvre of `law` onto `prior` sweeps from `here`
  /// (rear axle): target 1, the pivot at target 2, the realignment stand-off and the docked pose.
  std::vector<geometry::Vec2> docking(const control::DockingLaw& law, const geometry::Pose2& here,
                                      const geometry::Pose2& prior) const;
  /// The same for the manoeuvre at the end of `path` (the rear axle's), with the body standing
  /// there: what traffic holds as the route's arrival area.
  std::vector<geometry::Vec2> arrival(const std::vector<geometry::Vec2>& path, const control::DockingParams& params,
                                      const geometry::Pose2& prior) const;
  /// The way out of a dock or bay onto the road from `here` (rear axle): turning about the rear
  /// axle towards `path`, then along it to 1 m past the road's start, `road_start` metres in.
  std::vector<geometry::Vec2> way_out(const std::vector<geometry::Vec2>& path, const geometry::Pose2& here,
                                      double road_start) const;
  /// Moving up straight back from `here` to the rear axle at `to`, heading `yaw`.
  std::vector<geometry::Vec2> straight_back(const geometry::Pose2& here, geometry::Vec2 to, double yaw) const;
  /// The rear-axle position a route to a docking onto `prior` ends at: target 1's stand-off in
  /// front of it.
  geometry::Vec2 approach_of(const geometry::Pose2& prior) const;

 private:
  const StackerConfig& config_;
  geometry::Footprint footprint_;
};

}  // namespace fleet::robot
