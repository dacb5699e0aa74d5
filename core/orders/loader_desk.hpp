#pragma once
// The server's side of the loader jobs (docs/loader.md): for each pick order worked as a loader
// walk it keeps a LoaderJob, feeds it what the book and the robots' states show, asks for the
// transports its pallets need and turns its instructions into revisions of the job's orders. It
// decides; the server carries its actions out.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "map/site.hpp"
#include "orders/area_ledger.hpp"
#include "orders/loader_job.hpp"
#include "orders/order_book.hpp"
#include "orders/pick_lines.hpp"
#include "orders/robot_roster.hpp"

namespace fleet::orders {

/// Where the two robots of a loader job stand, and how many boxes a pallet takes.
struct LoaderLayout {
  /// Boxes a transporter's pallet takes: the row the picker's arm reaches, three across and two
  /// layers high (PickerArmLayout::deck; server.loader_pallet_boxes).
  int pallet_boxes = kLoaderPalletBoxes;
  /// The picker's centre out from a rack place's pose, side-on (task::ExecutorParams::item_standoff).
  double item_standoff = 1.0;
  /// The pallet's centre along the picker's heading from the picker's centre: behind it, its
  /// near edge just behind the 0.65 m base, its first row where the arm reaches.
  double deck_x = -1.0;
  /// A stacker's pallet centre behind its body's centre (forks 1.15 m, a 1.2 m pallet).
  double pallet_x = 0.35;
  /// A transporter STANDING this near the pose it was sent to is in place behind the picker.
  double in_place_m = 0.25;
  /// A transporter moving up straight ahead along its line this far from the stand it left: the
  /// picker may follow it to the next stop (LoaderTask::kApproach).
  double follow_after_m = 0.5;
  /// The fleet whose robots carry the pallets (a stacker fleet).
  std::string transporter_fleet;
};

/// Where the picker stands to pick at a rack place whose pose is `place`: `standoff` metres out
/// towards the road, side-on, the place on its left (as the pick tour's stops).
geometry::Pose2 picker_stop_pose(const geometry::Pose2& place, double standoff);

/// A transporter standing at `from` and sent to `to` moves up straight ahead along its line (the
/// same heading, `to` ahead of `from` on the line through it), and at `now` has come at least
/// `distance` metres along it: a picker behind its pallet can follow it without standing in its way.
bool moving_up_straight(const geometry::Pose2& from, const geometry::Pose2& to, const geometry::Pose2& now,
                        double distance);

/// What the desk reads each time it looks.
struct LoaderView {
  const OrderBook& book;
  const std::map<std::string, RobotEntry>& robots;
  const map::Site& site;
  const AreaLedger& ledger;
};

/// What the server is to do for a loader job.
struct LoaderAction {
  enum class Kind {
    kCreate,  ///< add `draft` (a transport for the job's next pallet) to the book
    kRevise,  ///< tell order `order_id`'s robot `revision` (OrderBook::revise)
  };
  Kind kind = Kind::kRevise;
  Order draft{};
  std::int64_t order_id = 0;
  OrderRevision revision{};
  std::string why;  ///< for the log
};

class LoaderDesk {
 public:
  explicit LoaderDesk(LoaderLayout layout) : layout_(std::move(layout)) {}

  /// Looks at every loader job once: what the robots did since, then what each is to do now.
  std::vector<LoaderAction> step(const LoaderView& view);

  /// The server added a kCreate action's draft to the book as `transport`.
  void transport_created(const Order& transport);

  /// The job of pick order `pick_id`, or null (not a loader order, or over).
  const LoaderJob* job_of(std::int64_t pick_id) const;
  /// Whether `order` may go to a robot: a loader pick order once its first pallet stands behind
  /// the walk's first stop. Until then the walk waits in the queue, not a picker: the server pairs
  /// a picker with a stacker that carries an empty pallet, and the stacker fetches the pallet and
  /// takes it to the first stop while the pickers do other work. True for any other order.
  bool ready_for_picker(const Order& order) const;
  const LoaderLayout& layout() const { return layout_; }
  /// The robots that work together now, each transporter to its picker: the one behind the
  /// picker, and one leaving with a full pallet until it has delivered it. A transporter of a walk
  /// no picker works (yet) maps to the empty string.
  std::map<std::string, std::string> partners() const;
  /// Pick orders whose job is under way.
  std::vector<std::int64_t> jobs() const;
  /// The expedition places kept for the pallets of the jobs' transports: from the moment a pallet
  /// is asked for it has a place to go once full, so that it never stands full in a rack lane for
  /// want of one. Random transports leave them alone (IntakeView::reserved).
  std::set<std::string> reserved_places() const;

 private:
  struct Transport {
    std::string robot_id;                       ///< once assigned and added to the job
    int stand_stop = -1;                        ///< the stop behind which its current stand pose lies
    std::optional<geometry::Pose2> left_stand;  ///< the stand it held before that one
    std::string expedition;                     ///< the full_pallets_to place kept for its pallet
  };
  struct Entry {
    LoaderJob job;
    std::map<std::int64_t, Transport> transports;  ///< the job's transport orders, by id
    bool ended = false;                            ///< the pick order ended: no stop is left to load
    bool pallet_ready = false;                     ///< its first pallet stood behind the first stop
  };

  /// What the pick order and its robot show: the picker's stop and the boxes it loaded.
  void take_picker_facts(Entry& entry, const Order& pick, const LoaderView& view) const;
  /// What the transports and their robots show: joined, in place, delivered, lost.
  void take_transport_facts(Entry& entry, const LoaderView& view) const;
  /// A transport for the next pallet, when the job wants one and none is waiting for a robot;
  /// the places it counts on go into `taken`.
  void ask_for_transporter(const Entry& entry, const Order& pick, const LoaderView& view,
                           std::vector<LoaderAction>& actions, std::vector<std::string>& taken) const;
  /// The revisions the job's instructions ask for.
  void revise_orders(Entry& entry, const Order& pick, const LoaderView& view, std::vector<LoaderAction>& actions) const;
  /// A place of `places` that holds a load (`with_load`) or none, promised to no open order.
  /// Places kept for a transport's pallet (Transport::expedition) count as taken, but `own`'s, and
  /// so do those in `taken`.
  std::string free_place(const std::vector<std::string>& places, bool with_load, const LoaderView& view,
                         const std::string& own = {}, const std::vector<std::string>& taken = {}) const;
  /// Takes on the open transports of the book that bring or hold a pallet for pick order
  /// `pick_id`: its job was under way before this desk started.
  void adopt_transports(Entry& entry, std::int64_t pick_id, const LoaderView& view) const;
  /// Keeps an expedition place for each transport of the job that has none and is not over.
  void keep_expedition_places(Entry& entry, const LoaderView& view);

  LoaderLayout layout_;
  std::map<std::int64_t, Entry> jobs_;  ///< by pick order id
};

}  // namespace fleet::orders
