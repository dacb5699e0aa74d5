#include "aisle/hough_lines.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fleet::aisle {

using geometry::Vec2;

namespace {

constexpr double kPi = std::numbers::pi;

/// Puts a normal angle back into [0, pi), flipping rho with it so that the line stays the same.
HoughLine normalised(double theta, double rho, int votes) {
  while (theta >= kPi) {
    theta -= kPi;
    rho = -rho;
  }
  while (theta < 0.0) {
    theta += kPi;
    rho = -rho;
  }
  return {theta, rho, votes};
}

double signed_distance(const HoughLine& line, Vec2 p) {
  return p.x * std::cos(line.theta) + p.y * std::sin(line.theta) - line.rho;
}

/// Perpendicular spacing of two nearly parallel lines and their mean direction, weighted by their votes.
void measure_pair(RackLinePair& pair) {
  const double wl = std::max(pair.left.votes, 1);
  const double wr = std::max(pair.right.votes, 1);
  pair.heading = (wl * pair.left.direction() + wr * pair.right.direction()) / (wl + wr);
  pair.width = (pair.left.lateral_offset() - pair.right.lateral_offset()) * std::cos(pair.heading);
}

/// Returns lying between the two faces, each face's own noise band excluded. [Picker thesis, Algorithm 3, lines 36-41]
/// tests the x-coordinates against both lines; the signed distances below are the same test in metres.
int count_between(const HoughLine& left, const HoughLine& right, std::span<const Vec2> points, double margin) {
  int count = 0;
  for (const Vec2& p : points) {
    if (-left.outward_distance(p) > margin && -right.outward_distance(p) > margin) ++count;
  }
  return count;
}

}  // namespace

std::array<LidarMount, 2> picker_lidar_mounts(double base_length, double base_width) {
  if (!(base_length > 0.0) || !(base_width > 0.0)) throw std::invalid_argument("picker_lidar_mounts: size must be > 0");
  LidarMount front_right;
  front_right.pose = {0.5 * base_length, -0.5 * base_width, -kPi / 4.0};
  LidarMount rear_left;
  rear_left.pose = {-0.5 * base_length, 0.5 * base_width, 3.0 * kPi / 4.0};
  return {front_right, rear_left};
}

std::vector<Vec2> virtual_range_image(std::span<const planning::LidarScan> scans, std::span<const LidarMount> mounts,
                                      const RangeImageExtent& extent) {
  if (scans.size() != mounts.size()) throw std::invalid_argument("virtual_range_image: one mount per scan");
  std::vector<Vec2> points;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    const planning::LidarScan& scan = scans[s];
    const LidarMount& mount = mounts[s];
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      const double r = scan.ranges[i];
      if (!std::isfinite(r) || r < mount.min_range || r > mount.max_range) continue;
      const double beam = geometry::normalize_angle(scan.angle_min + static_cast<double>(i) * scan.angle_increment);
      if (std::abs(beam) > 0.5 * mount.field_of_view + 1e-9) continue;
      // [Picker thesis, eq. 4.20] in the sensor frame, then [Picker thesis, eq. 4.21] into the base frame; the seed's
      // image offsets (w/2, h/2) and pixel scale are left out: the image here is metric with the base centre at the
      // origin.
      const Vec2 p = geometry::body_to_map(mount.pose, {r * std::cos(beam), r * std::sin(beam)});
      if (std::abs(p.x) <= extent.half_length && std::abs(p.y) <= extent.half_width) points.push_back(p);
    }
  }
  return points;
}

double HoughLine::lateral_offset() const {
  return rho / std::sin(theta);
}

double HoughLine::outward_distance(Vec2 p) const {
  // The base centre is at signed distance -rho; outward is the other sign.
  const double d = signed_distance(*this, p);
  return rho >= 0.0 ? d : -d;
}

HoughAccumulator::HoughAccumulator(const HoughParams& params, double max_rho) : params_(params) {
  if (!(params.angle_step > 0.0) || !(params.rho_step > 0.0) || !(max_rho > 0.0) || params.peak_window < 1 ||
      params.max_lines == 0) {
    throw std::invalid_argument("HoughAccumulator: steps, max_rho, peak_window and max_lines must be positive");
  }
  theta_bins_ = static_cast<int>(std::lround(kPi / params.angle_step));
  rho_centre_ = static_cast<int>(std::ceil(max_rho / params.rho_step));
  rho_bins_ = 2 * rho_centre_ + 1;
  cos_.resize(static_cast<std::size_t>(theta_bins_));
  sin_.resize(static_cast<std::size_t>(theta_bins_));
  for (int t = 0; t < theta_bins_; ++t) {
    cos_[static_cast<std::size_t>(t)] = std::cos(theta_of(t));
    sin_[static_cast<std::size_t>(t)] = std::sin(theta_of(t));
  }
  cells_.assign(static_cast<std::size_t>(theta_bins_) * static_cast<std::size_t>(rho_bins_), 0);
  const int half = theta_bins_ / 2;
  const int reach = static_cast<int>(std::ceil(params.max_heading / params.angle_step - 1e-9)) + params.peak_window;
  first_voted_ = std::max(0, half - reach);
  last_voted_ = std::min(theta_bins_ - 1, half + reach);
}

int HoughAccumulator::votes(int theta_index, int rho_index) const {
  return cells_[static_cast<std::size_t>(theta_index) * static_cast<std::size_t>(rho_bins_) +
                static_cast<std::size_t>(rho_index)];
}

void HoughAccumulator::vote(std::span<const Vec2> points) {
  std::fill(cells_.begin(), cells_.end(), 0);
  const double per_cell = 1.0 / params_.rho_step;
  const double offset = rho_centre_ + 0.5;  // cell centres at multiples of rho_step; floor of a positive value
  // θ outermost: each row of the accumulator stays in cache while every point votes in it.
  for (int t = first_voted_; t <= last_voted_; ++t) {
    const double c = cos_[static_cast<std::size_t>(t)] * per_cell;
    const double s = sin_[static_cast<std::size_t>(t)] * per_cell;
    int* row = cells_.data() + static_cast<std::size_t>(t) * static_cast<std::size_t>(rho_bins_);
    for (const Vec2& p : points) {
      const double cell = p.x * c + p.y * s + offset;  // [Picker thesis, eq. 4.19] in cells
      if (cell >= 0.0 && cell < rho_bins_) ++row[static_cast<std::size_t>(cell)];
    }
  }
}

bool HoughAccumulator::is_local_peak(int theta_index, int rho_index) const {
  const int v = votes(theta_index, rho_index);
  const int w = params_.peak_window;
  for (int dt = -w; dt <= w; ++dt) {
    for (int dj = -w; dj <= w; ++dj) {
      if (dt == 0 && dj == 0) continue;
      int t = theta_index + dt;
      int j = rho_index + dj;
      // θ wraps at 180°, where the same line has the opposite ρ.
      if (t < 0 || t >= theta_bins_) {
        t = (t + theta_bins_) % theta_bins_;
        j = rho_bins_ - 1 - j;
      }
      if (j < 0 || j >= rho_bins_) continue;
      const int n = votes(t, j);
      // Of equal neighbours on a plateau only the first in scan order is a peak.
      if (n > v || (n == v && (dt < 0 || (dt == 0 && dj < 0)))) return false;
    }
  }
  return true;
}

std::vector<HoughLine> HoughAccumulator::peaks() const {
  std::vector<HoughLine> out;
  for (int t = 0; t < theta_bins_; ++t) {
    if (std::abs(theta_of(t) - kPi / 2.0) > params_.max_heading + 1e-9) continue;
    for (int j = 0; j < rho_bins_; ++j) {
      const int v = votes(t, j);
      if (v > params_.vote_limit && is_local_peak(t, j)) out.push_back({theta_of(t), rho_of(j), v});
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const HoughLine& a, const HoughLine& b) { return a.votes > b.votes; });
  if (out.size() > params_.max_lines) out.resize(params_.max_lines);
  return out;
}

std::string_view to_string(PairStatus status) {
  switch (status) {
    case PairStatus::kFound:
      return "found";
    case PairStatus::kTooFewPoints:
      return "too few points";
    case PairStatus::kNoLines:
      return "no lines";
    case PairStatus::kNoLineLeft:
      return "no line on the left";
    case PairStatus::kNoLineRight:
      return "no line on the right";
    case PairStatus::kNoPairInWidth:
      return "no pair within the rack width";
    case PairStatus::kNotParallel:
      return "no parallel pair";
  }
  return "unknown";
}

RackLinePair select_rack_pair(std::span<const HoughLine> lines, std::span<const Vec2> points,
                              const RackLineParams& all) {
  const PairParams& params = all.pair;
  const double image_length = 2.0 * all.image.half_length;
  RackLinePair best;
  best.candidates = lines.size();
  if (lines.empty()) return best;
  const bool any_left =
      std::any_of(lines.begin(), lines.end(), [](const HoughLine& l) { return l.lateral_offset() > 0; });
  const bool any_right =
      std::any_of(lines.begin(), lines.end(), [](const HoughLine& l) { return l.lateral_offset() < 0; });
  if (!any_left) {
    best.status = PairStatus::kNoLineLeft;
    return best;
  }
  if (!any_right) {
    best.status = PairStatus::kNoLineRight;
    return best;
  }
  const double min_width = (1.0 - params.width_tolerance) * params.rack_width;
  const double max_width = (1.0 + params.width_tolerance) * params.rack_width;
  bool any_in_width = false;
  double best_criterion = std::numeric_limits<double>::infinity();
  for (const HoughLine& left : lines) {
    if (left.lateral_offset() <= 0.0) continue;  // [Picker thesis, Algorithm 3, lines 28-29]: one line each side
    for (const HoughLine& right : lines) {
      if (right.lateral_offset() >= 0.0) continue;
      RackLinePair pair;
      pair.left = left;
      pair.right = right;
      measure_pair(pair);
      // The spacing is measured across the lines, not along the body's y axis as the seed's midpoints are: at a
      // heading error e_θ those overstate the width by 1/cos(e_θ), 10 % at the 25° of the seed's test III.
      if (pair.width < min_width || pair.width > max_width) continue;
      any_in_width = true;
      if (std::abs(left.direction() - right.direction()) > params.max_parallel_error) continue;
      // [Picker thesis, eq. 4.23]; the determinant of [Picker thesis, Algorithm 3, line 33] is the difference of the
      // two lines' lateral runs over the image length, here in metres (the seed's pixels have no stated size). In ρ
      // cells a 1° difference between two faces, which the 1° θ step gives by itself, would weigh more than hundreds of
      // returns between them.
      const double determinant = image_length * (std::tan(left.direction()) - std::tan(right.direction()));
      pair.points_between = count_between(left, right, points, params.between_margin);
      pair.criterion =
          (1.0 + pair.points_between) * (1.0 + std::abs(determinant)) / static_cast<double>(left.votes + right.votes);
      if (pair.criterion < best_criterion) {
        best_criterion = pair.criterion;
        pair.status = PairStatus::kFound;
        best = pair;
      }
    }
  }
  if (!best.found()) best.status = any_in_width ? PairStatus::kNotParallel : PairStatus::kNoPairInWidth;
  best.candidates = lines.size();
  return best;
}

HoughLine refit_line(const HoughLine& line, std::span<const Vec2> points, double band) {
  double sx = 0.0;
  double sy = 0.0;
  int n = 0;
  for (const Vec2& p : points) {
    if (std::abs(signed_distance(line, p)) > band) continue;
    sx += p.x;
    sy += p.y;
    ++n;
  }
  if (n < 2) return line;
  const double cx = sx / n;
  const double cy = sy / n;
  double sxx = 0.0;
  double syy = 0.0;
  double sxy = 0.0;
  for (const Vec2& p : points) {
    if (std::abs(signed_distance(line, p)) > band) continue;
    sxx += (p.x - cx) * (p.x - cx);
    syy += (p.y - cy) * (p.y - cy);
    sxy += (p.x - cx) * (p.y - cy);
  }
  // The principal axis of the points is the line's direction; its normal is a quarter turn on.
  const double axis = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const double theta = axis + kPi / 2.0;
  return normalised(theta, cx * std::cos(theta) + cy * std::sin(theta), line.votes);
}

HoughLine shift_to_mode(const HoughLine& line, std::span<const Vec2> points, double scale) {
  HoughLine out = line;
  const double window = 5.0 * scale;
  for (int iteration = 0; iteration < 10; ++iteration) {
    double weights = 0.0;
    double weighted = 0.0;
    for (const Vec2& p : points) {
      const double r = signed_distance(out, p);
      if (std::abs(r) > window) continue;
      const double w = std::exp(-0.5 * r * r / (scale * scale));
      weights += w;
      weighted += w * r;
    }
    if (weights <= 0.0) break;
    const double step = weighted / weights;
    out.rho += step;
    if (std::abs(step) < 1e-5) break;
  }
  return out;
}

RackLineDetector::RackLineDetector(const RackLineParams& params)
    : params_(params), accumulator_(params.hough, std::hypot(params.image.half_length, params.image.half_width)) {
  if (!(params.pair.rack_width > 0.0) || !(params.pair.width_tolerance >= 0.0) ||
      !(params.pair.between_margin >= 0.0) || !(params.pair.refine_band > 0.0) || !(params.pair.mode_scale > 0.0)) {
    throw std::invalid_argument("RackLineDetector: rack_width, refine_band and mode_scale > 0, tolerances >= 0");
  }
}

RackLinePair RackLineDetector::detect(std::span<const Vec2> points) {
  lines_.clear();
  RackLinePair out;
  if (points.size() <= static_cast<std::size_t>(std::max(params_.hough.vote_limit, 1))) {
    out.status = PairStatus::kTooFewPoints;
    return out;
  }
  accumulator_.vote(points);
  lines_ = accumulator_.peaks();
  if (lines_.empty()) return out;
  out = select_rack_pair(lines_, points, params_);
  if (out.found() && params_.pair.refine) {
    // Twice: the first fit moves the band onto the face, the second fits within it.
    for (int i = 0; i < 2; ++i) {
      out.left = refit_line(out.left, points, params_.pair.refine_band);
      out.right = refit_line(out.right, points, params_.pair.refine_band);
    }
    out.left = shift_to_mode(out.left, points, params_.pair.mode_scale);
    out.right = shift_to_mode(out.right, points, params_.pair.mode_scale);
    measure_pair(out);
  }
  return out;
}

RackLinePair RackLineDetector::detect(std::span<const planning::LidarScan> scans, std::span<const LidarMount> mounts) {
  const std::vector<Vec2> points = virtual_range_image(scans, mounts, params_.image);
  return detect(points);
}

}  // namespace fleet::aisle
