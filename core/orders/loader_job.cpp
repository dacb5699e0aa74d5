#include "orders/loader_job.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "common/errors.hpp"

namespace fleet::orders {

namespace {

/// From `left[first]` always on to the nearest by `distance`; `length` is the walk's road length.
std::vector<PickLine> nearest_next_walk(std::vector<PickLine> left, std::size_t first, const PlaceDistance& distance,
                                        double& length) {
  std::vector<PickLine> walk;
  walk.reserve(left.size());
  length = 0.0;
  std::size_t next = first;
  while (!left.empty()) {
    if (!walk.empty()) {
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < left.size(); ++k) {
        const double d = left[k].place == walk.back().place ? 0.0 : distance(walk.back().place, left[k].place);
        if (d < nearest) nearest = d, next = k;
      }
      length += nearest;
    }
    walk.push_back(left[next]);
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(next));
  }
  return walk;
}

}  // namespace

std::vector<PickLine> loader_walk(const std::vector<PickLine>& lines, int capacity,
                                  const std::map<std::string, geometry::Pose2>& poses, const PlaceDistance& distance) {
  std::vector<PickLine> stops;
  for (const PickTour& tour : plan_tours(lines, capacity, poses))
    stops.insert(stops.end(), tour.lines.begin(), tour.lines.end());
  // The shortest of the walks from each start: on a one-way lane that starts at its upstream end,
  // so that the walk goes down the lane (the first in aisle order when they are as long).
  std::vector<PickLine> best;
  double best_length = std::numeric_limits<double>::infinity();
  for (std::size_t first = 0; first < stops.size(); ++first) {
    double length = 0.0;
    std::vector<PickLine> walk = nearest_next_walk(stops, first, distance, length);
    if (best.empty() || length < best_length - 1e-9) best = std::move(walk), best_length = length;
  }
  return best;
}

geometry::Pose2 transporter_pose(const geometry::Pose2& picker, double deck_x, double pallet_x) {
  // The pallet's centre lies deck_x along the picker's heading; the transporter faces the other
  // way, so its centre lies pallet_x further along the same line, away from the picker.
  const double along = deck_x - pallet_x;
  return {picker.x + along * std::cos(picker.yaw), picker.y + along * std::sin(picker.yaw),
          geometry::normalize_angle(picker.yaw + std::numbers::pi)};
}

const char* to_string(LoaderTask task) {
  switch (task) {
    case LoaderTask::kGoToStop:
      return "go to stop";
    case LoaderTask::kLoad:
      return "load";
    case LoaderTask::kApproach:
      return "approach";
    case LoaderTask::kFollow:
      return "follow";
    case LoaderTask::kWaitBehind:
      return "wait behind";
    case LoaderTask::kDeliver:
      return "deliver";
    case LoaderTask::kWait:
      return "wait";
    case LoaderTask::kRelease:
      return "release";
  }
  return "?";
}

LoaderJob::LoaderJob(std::vector<PickLine> walk, int capacity, std::string picker_id)
    : walk_(std::move(walk)),
      capacity_(capacity),
      loaded_(walk_.size(), 0),
      failed_(walk_.size(), false),
      picker_id_(std::move(picker_id)) {
  if (capacity_ < 1)
    throw InputError("a loader job needs pallets that hold at least one box, not " + std::to_string(capacity_));
  for (const PickLine& stop : walk_) {
    if (stop.quantity < 1 || stop.quantity > capacity_) {
      throw InputError("loader stop at " + stop.place + " asks for " + std::to_string(stop.quantity) +
                       " boxes; a stop takes 1 to " + std::to_string(capacity_) + " (one pallet)");
    }
  }
}

int LoaderJob::left_at(int stop) const {
  return failed_[stop] ? 0 : walk_[stop].quantity - loaded_[stop];
}

int LoaderJob::room() const {
  const PalletRun* run = current_run();
  return run ? capacity_ - run->boxes : 0;
}

std::string LoaderJob::current_transporter() const {
  const PalletRun* run = current_run();
  return run ? run->transporter_id : std::string();
}

bool LoaderJob::pallet_in_place() const {
  const int stop = next_stop();
  return current_ && !all_loaded() && transporter_at_ == stop && left_at(stop) <= room();
}

int LoaderJob::next_stop() const {
  int stop = 0;
  while (stop < static_cast<int>(walk_.size()) && left_at(stop) == 0) ++stop;
  return stop;
}

int LoaderJob::boxes_asked() const {
  return std::accumulate(walk_.begin(), walk_.end(), 0, [](int n, const PickLine& l) { return n + l.quantity; });
}

int LoaderJob::boxes_loaded() const {
  return std::accumulate(loaded_.begin(), loaded_.end(), 0);
}

PalletRun* LoaderJob::current_run() {
  return current_ ? &runs_[*current_] : nullptr;
}

const PalletRun* LoaderJob::current_run() const {
  return current_ ? &runs_[*current_] : nullptr;
}

void LoaderJob::picker_at(const std::string& robot_id, int stop) {
  if (robot_id == picker_id_) picker_at_ = stop;
}

void LoaderJob::transporter_in_place(const std::string& robot_id, int stop) {
  if (const PalletRun* run = current_run(); run && run->transporter_id == robot_id) transporter_at_ = stop;
}

void LoaderJob::transporter_moving_up(const std::string& robot_id, int stop) {
  moving_up_id_ = robot_id;
  moving_up_to_ = stop;
}

void LoaderJob::loaded(int stop, int boxes) {
  PalletRun* run = current_run();
  if (!run || stop != next_stop() || boxes < 0 || boxes > left_at(stop) || boxes > room()) {
    throw std::logic_error("loader job: " + std::to_string(boxes) + " boxes loaded at stop " + std::to_string(stop) +
                           ", which is not the stop under way or has no pallet with room for them");
  }
  loaded_[stop] += boxes;
  run->boxes += boxes;
  const int next = next_stop();
  // The next stop at the same place: both robots already stand there.
  if (next != stop && next < static_cast<int>(walk_.size()) && walk_[next].place == walk_[stop].place) {
    if (picker_at_ == stop) picker_at_ = next;
    if (transporter_at_ == stop) transporter_at_ = next;
  }
  settle_runs();
}

void LoaderJob::stop_failed(int stop) {
  if (stop < 0 || stop >= static_cast<int>(walk_.size())) return;
  failed_[stop] = true;
  settle_runs();
}

void LoaderJob::delivered(const std::string& robot_id) {
  for (PalletRun& run : runs_) {
    if (run.transporter_id == robot_id && run.leaving && !run.delivered) run.delivered = true;
  }
}

void LoaderJob::robot_lost(const std::string& robot_id) {
  if (robot_id == picker_id_) {
    // The boxes in its gripper were never counted: they go back to their place.
    picker_id_.clear();
    picker_at_ = -1;
  }
  if (robot_id == next_transporter_) next_transporter_.clear();
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    PalletRun& run = runs_[i];
    if (run.transporter_id != robot_id || run.delivered || run.lost) continue;
    run.lost = true;  // its boxes stay on its pallet
    if (current_ == i) {
      current_.reset();
      transporter_at_ = -1;
      transporter_lost_ = true;
    }
  }
  settle_runs();
}

void LoaderJob::add_transporter(const std::string& robot_id) {
  if (!current_) {
    runs_.push_back({.transporter_id = robot_id});
    current_ = runs_.size() - 1;
    transporter_at_ = -1;
    transporter_lost_ = false;
  } else if (next_transporter_.empty()) {
    next_transporter_ = robot_id;
  } else {
    throw std::logic_error("loader job: transporter " + robot_id + " added while " + next_transporter_ +
                           " already waits behind " + runs_[*current_].transporter_id);
  }
  settle_runs();
}

void LoaderJob::add_picker(const std::string& robot_id) {
  if (!picker_id_.empty()) {
    throw std::logic_error("loader job: picker " + robot_id + " added while " + picker_id_ + " works it");
  }
  picker_id_ = robot_id;
  picker_at_ = -1;
}

void LoaderJob::settle_runs() {
  if (PalletRun* run = current_run()) {
    const bool last = all_loaded();
    if (last || left_at(next_stop()) > room()) {
      if (run->boxes > 0) run->leaving = true;
      // An empty pallet at the end of the walk has nothing to deliver: its transporter is released.
      if (run->boxes == 0) runs_.erase(runs_.begin() + static_cast<std::ptrdiff_t>(*current_));
      current_.reset();
      transporter_at_ = -1;
    }
  }
  if (!current_ && !next_transporter_.empty() && !all_loaded()) {
    runs_.push_back({.transporter_id = next_transporter_});
    current_ = runs_.size() - 1;
    next_transporter_.clear();
    transporter_at_ = -1;
    transporter_lost_ = false;
  }
}

bool LoaderJob::wants_transporter() const {
  if (all_loaded()) return false;
  if (!current_) return next_transporter_.empty();
  int left = 0;
  for (int stop = next_stop(); stop < static_cast<int>(walk_.size()); ++stop) left += left_at(stop);
  return next_transporter_.empty() && left > room();
}

bool LoaderJob::done() const {
  if (!all_loaded()) return false;
  for (const PalletRun& run : runs_) {
    if (!run.delivered && !run.lost) return false;
  }
  return true;
}

std::vector<LoaderInstruction> LoaderJob::instructions() const {
  std::vector<LoaderInstruction> out;
  const int stop = next_stop();
  const bool loaded_all = all_loaded();
  if (!picker_id_.empty()) {
    LoaderInstruction picker{.robot_id = picker_id_};
    if (loaded_all) {
      picker.task = LoaderTask::kRelease;
    } else if (transporter_lost_) {
      picker.task = LoaderTask::kWait;
    } else if (pallet_in_place()) {
      // The stop is released once the pallet stands behind it: the picker drives in behind the
      // transporter, never the other way round (on a one-way lane it could not pass the picker).
      picker = picker_at_ == stop ? LoaderInstruction{picker_id_, LoaderTask::kLoad, stop, left_at(stop)}
                                  : LoaderInstruction{picker_id_, LoaderTask::kGoToStop, stop, 0};
    } else if (const PalletRun* run = current_run(); run && run->boxes > 0 && run->transporter_id == moving_up_id_ &&
                                                     moving_up_to_ == stop && left_at(stop) <= room()) {
      // The pallet it loaded moves up ahead of it: it follows, and waits at the stop to load.
      picker = {picker_id_, LoaderTask::kApproach, stop, 0};
    } else {
      // Where it stands behind the pallet moving up, or out of the aisle for a new one.
      picker = {picker_id_, LoaderTask::kWait, stop, 0};
    }
    out.push_back(picker);
  }
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    const PalletRun& run = runs_[i];
    if (run.delivered || run.lost) continue;
    // With no picker yet (or none since one was lost) the pallet goes ahead to the next stop: the
    // picker is called once it stands there (pallet_in_place).
    out.push_back(run.leaving ? LoaderInstruction{run.transporter_id, LoaderTask::kDeliver, -1, run.boxes}
                              : LoaderInstruction{run.transporter_id, LoaderTask::kFollow, stop, 0});
  }
  if (!next_transporter_.empty()) {
    out.push_back({next_transporter_, loaded_all ? LoaderTask::kRelease : LoaderTask::kWaitBehind, -1, 0});
  }
  return out;
}

}  // namespace fleet::orders
