#pragma once
// A pick list done by two robots together [Picker thesis, section 4.3.3.1]: a picker, the loader,
// walks the list's places and sets each box straight on the pallet of a transporter (a stacker)
// standing behind it; when the pallet is full, the transporter leaves for expedition and the next
// one, waiting behind, moves up. LoaderJob decides who does what next from what the robots report;
// the server carries its instructions out. docs/loader.md describes the job.
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "orders/pick_lines.hpp"

namespace fleet::orders {

/// Road metres from one place to another (+inf when there is no way).
using PlaceDistance = std::function<double(const std::string& from, const std::string& to)>;

/// The lines as one walk, as the picker visits them: merged by place and cut where a pallet of
/// `capacity` boxes fills in aisle order (plan_tours: no line holds more than a pallet), then from
/// a first stop always on to the nearest by `distance`: of the walks from each first stop, the
/// shortest by road (on a one-way lane, the one down the lane), the first in aisle order among
/// equals. A walk, not tours: a loader never goes back to a station between its boxes.
std::vector<PickLine> loader_walk(const std::vector<PickLine>& lines, int capacity,
                                  const std::map<std::string, geometry::Pose2>& poses, const PlaceDistance& distance);

/// Where a transporter stands for the picker standing at `picker` to reach its pallet: the
/// pallet's centre `deck_x` metres along the picker's heading from the picker's centre (negative:
/// behind it), the transporter facing away with its forks towards the picker and the pallet's
/// centre `pallet_x` metres behind its own centre (a stacker carries its pallet on forks at its
/// back).
geometry::Pose2 transporter_pose(const geometry::Pose2& picker, double deck_x, double pallet_x);

/// What a robot of a loader job is to do now.
enum class LoaderTask {
  kGoToStop,    ///< picker: drive to stand beside the stop's place (its transporter stands behind it)
  kApproach,    ///< picker: follow its transporter moving up to the stop; load once it stands there
  kLoad,        ///< picker: set the stop's boxes on the transporter's pallet (both stand in place)
  kFollow,      ///< transporter: stand behind the picker's stop, its pallet at the arm's height
  kWaitBehind,  ///< next transporter: stand behind the current one, ready to move up
  kDeliver,     ///< transporter: take its pallet to expedition
  kWait,        ///< picker: until its transporter stands behind `stop` (or, -1, one takes over)
  kRelease,     ///< out of the job: free for other work
};
const char* to_string(LoaderTask task);

struct LoaderInstruction {
  std::string robot_id;
  LoaderTask task = LoaderTask::kWait;
  int stop = -1;  ///< the stop concerned (kGoToStop, kLoad, kFollow), else -1
  int boxes = 0;  ///< kLoad: boxes to set on the pallet
  bool operator==(const LoaderInstruction&) const = default;
};

/// The boxes one transporter took: they belong to its pallet from the moment they are set on it.
struct PalletRun {
  std::string transporter_id;
  int boxes = 0;
  bool leaving = false;    ///< full or last: on its way to expedition
  bool delivered = false;  ///< put down at expedition
  bool lost = false;       ///< its transporter was lost: the boxes stay on its pallet, wherever it stands
};

/// A loader job's progress and its rules. Stops are done in order; a stop's boxes go on one
/// pallet (a walk's line never holds more than a pallet). The picker drives to a stop only once
/// the current transporter stands behind it with room for the stop's boxes, and loads when it
/// stands there; else the transporter leaves full and the next one moves up. A lost robot leaves the job to a robot of
/// its fleet: the boxes on a lost transporter's pallet stay on that pallet (its run), the boxes a
/// lost picker held were never counted (they go back to their place).
class LoaderJob {
 public:
  /// Throws InputError when `capacity` < 1, a stop holds no box or more than `capacity`.
  LoaderJob(std::vector<PickLine> walk, int capacity, std::string picker_id);

  // What the robots report.
  /// The picker stands beside stop `stop`.
  void picker_at(const std::string& robot_id, int stop);
  /// A transporter stands behind stop `stop` (the current one) or behind the current transporter
  /// (the next one, `stop` -1).
  void transporter_in_place(const std::string& robot_id, int stop);
  /// The current transporter left its stand and moves up straight ahead along its line to stand
  /// behind stop `stop`: the picker, ahead of the pallet it loaded, can follow it there and never
  /// stand in its way.
  void transporter_moving_up(const std::string& robot_id, int stop);
  /// The arm set `boxes` boxes of stop `stop` on the current transporter's pallet.
  void loaded(int stop, int boxes);
  /// The arm cannot take the rest of stop `stop` (no box found, out of reach): the boxes left
  /// stay at their place and the walk goes on.
  void stop_failed(int stop);
  /// A transporter put its pallet down at expedition.
  void delivered(const std::string& robot_id);
  /// A robot of the job is lost, stopped or faulted: it leaves the job to another.
  void robot_lost(const std::string& robot_id);

  // What the server found for it.
  /// A transporter with an empty pallet joins: the current one when there is none, else the next.
  void add_transporter(const std::string& robot_id);
  /// A picker takes over from a lost one, at the first stop not done.
  void add_picker(const std::string& robot_id);

  /// What each robot of the job is to do now, the picker first.
  std::vector<LoaderInstruction> instructions() const;
  /// The job wants another transporter: none is current, or the current one's pallet cannot take
  /// the stops left and none waits behind it.
  bool wants_transporter() const;
  bool wants_picker() const { return picker_id_.empty() && !all_loaded(); }
  /// Every stop loaded and every pallet delivered.
  bool done() const;

  const std::vector<PickLine>& walk() const { return walk_; }
  const std::vector<PalletRun>& runs() const { return runs_; }
  const std::string& picker_id() const { return picker_id_; }
  int boxes_asked() const;
  int boxes_loaded() const;
  /// The first stop not fully loaded (walk().size() once every one is).
  int next_stop() const;
  /// Every stop loaded or left.
  bool all_loaded() const { return next_stop() >= static_cast<int>(walk_.size()); }
  /// Boxes of stop `stop` still to load (0 for a stop left).
  int left_at(int stop) const;
  /// Boxes the current transporter's pallet still takes (0 without one).
  int room() const;
  /// The transporter whose pallet stands behind the picker, or empty.
  std::string current_transporter() const;
  /// The current transporter stands behind the next stop with room for its boxes: a picker
  /// sent now finds its pallet there.
  bool pallet_in_place() const;

 private:
  /// The current run (the pallet behind the picker), or null.
  PalletRun* current_run();
  const PalletRun* current_run() const;
  /// The current transporter's pallet leaves when it cannot take the next stop's boxes, or when
  /// every stop is loaded; the next transporter moves up.
  void settle_runs();

  std::vector<PickLine> walk_;
  int capacity_;
  std::vector<int> loaded_;   ///< boxes set on a pallet, per stop
  std::vector<bool> failed_;  ///< stops the arm gave up on
  std::string picker_id_;
  int picker_at_ = -1;  ///< the stop the picker stands at, -1 while driving
  std::vector<PalletRun> runs_;
  std::optional<std::size_t> current_;  ///< index into runs_
  std::string next_transporter_;        ///< waiting behind the current one
  int transporter_at_ = -1;             ///< the stop the current transporter stands behind, -1 while moving
  std::string moving_up_id_;            ///< the transporter last seen moving up straight ahead
  int moving_up_to_ = -1;               ///< ... to stand behind this stop
  bool transporter_lost_ = false;       ///< the current transporter was lost and none took over yet
};

}  // namespace fleet::orders
