#include "perception/pallet_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace fleet::perception {

using geometry::Vec2;

namespace {

Vec2 xy(const Vec3& v) {
  return {v.x, v.y};
}
Vec2 heading(double yaw) {
  return {std::cos(yaw), std::sin(yaw)};
}

std::string format(const char* fmt, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

/// A pallet face in the floor plane: its midpoint, its outward normal (towards the camera) and
/// the direction along it.
struct FaceFrame {
  Vec2 point;
  Vec2 normal;
  Vec2 along;
};

FaceFrame face_of(Vec2 point, Vec2 normal) {
  return {point, normal, {-normal.y, normal.x}};
}

/// The 800 mm face of `pallet` that turns towards the camera (both look the same).
FaceFrame facing_face(const geometry::Pose2& pallet, Vec2 camera_xy, double half_length) {
  Vec2 dir = heading(pallet.yaw);
  if (geometry::dot(dir, camera_xy - pallet.position()) < 0.0) dir = -1.0 * dir;
  return face_of(pallet.position() + half_length * dir, dir);
}

/// Extent of the searched volume around a face, metres: half along the face and half along
/// its normal, covering any pallet inside the docking area.
struct SearchExtent {
  double lateral = 0.0;
  double depth = 0.0;
};

SearchExtent search_extent(const PalletExpectation& expected, const PalletDetectorParams& params) {
  const DockingArea& a = expected.area;
  return {a.lateral_half + 0.5 * params.pallet.width + params.roi_margin,
          a.depth_half + 0.5 * params.pallet.width * std::sin(a.yaw_half) + params.roi_margin};
}

/// The region of interest: the searched volume projected into the image [Stacker thesis,
/// section 6.2.1]. A volume reaching behind the camera takes the whole image.
PixelWindow region_of_interest(const DepthCameraModel& camera, const CameraAxes& axes, const FaceFrame& face,
                               SearchExtent extent, double base_height, const PalletDetectorParams& params) {
  double col_min = camera.width, col_max = 0.0, row_min = camera.height, row_max = 0.0;
  for (double sl : {-extent.lateral, extent.lateral}) {
    for (double sd : {-extent.depth, extent.depth}) {
      for (double z : {base_height, base_height + params.pallet.height + params.roi_margin}) {
        const Vec2 p = face.point + sl * face.along + sd * face.normal;
        const auto image_point = project(camera, axes, {p.x, p.y, z});
        if (!image_point) return {0, camera.width, 0, camera.height};
        col_min = std::min(col_min, image_point->col);
        col_max = std::max(col_max, image_point->col);
        row_min = std::min(row_min, image_point->row);
        row_max = std::max(row_max, image_point->row);
      }
    }
  }
  const auto clamp_to = [](double v, int hi) { return std::clamp(static_cast<int>(std::floor(v)), 0, hi); };
  return {clamp_to(col_min, camera.width), clamp_to(col_max + 1.0, camera.width), clamp_to(row_min, camera.height),
          clamp_to(row_max + 1.0, camera.height)};
}

/// One pixel of the region of interest: its ray (unit optical-axis component) and depth.
struct Sample {
  Vec3 ray;
  double depth;  ///< NaN without a return
};

std::vector<Sample> gather(const DepthImage& image, const DepthCameraModel& camera, const CameraAxes& axes,
                           const PixelWindow& roi) {
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>(roi.col1 - roi.col0) * (roi.row1 - roi.row0));
  const PixelRays ray_through(camera, axes);
  for (int row = roi.row0; row < roi.row1; ++row) {
    for (int col = roi.col0; col < roi.col1; ++col) {
      samples.push_back({ray_through(col + 0.5, row + 0.5), image.at(col, row)});
    }
  }
  return samples;
}

/// Total least squares line through points: the face line, normal oriented towards `towards`.
FaceFrame fit_line(const std::vector<Vec2>& points, Vec2 towards) {
  Vec2 mean;
  for (Vec2 p : points) mean = mean + p;
  mean = (1.0 / points.size()) * mean;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (Vec2 p : points) {
    const Vec2 d = p - mean;
    sxx += d.x * d.x;
    sxy += d.x * d.y;
    syy += d.y * d.y;
  }
  const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // direction of largest spread
  Vec2 normal{-std::sin(angle), std::cos(angle)};
  if (geometry::dot(normal, towards - mean) < 0.0) normal = -1.0 * normal;
  return face_of(mean, normal);
}

/// The face line from the depth points in the region of interest (beyond the thesis): the
/// points at block and board height near the expected face, then least-squares fits that keep
/// the points ever closer to the line. Only this pallet's points take part, so that the faces of
/// its neighbours do not pull the fit: those of its board strip at first, those within
/// `guess_span` along a previous `guess` after a match. Without a guess, the start is the
/// densest depth along the expected normal (the deck's top, seen from above, spreads over the
/// pallet's whole length).
struct FaceFit {
  FaceFrame face;
  int points = 0;
};

/// The densest depth along the expected normal, metres.
double densest_depth(const std::vector<double>& depths, double half_range) {
  constexpr double bin = 0.02;
  const int bins = static_cast<int>(std::ceil(2.0 * half_range / bin)) + 1;
  std::vector<int> histogram(bins, 0);
  for (double d : depths) ++histogram[std::clamp(static_cast<int>((d + half_range) / bin), 0, bins - 1)];
  const int mode = static_cast<int>(std::max_element(histogram.begin(), histogram.end()) - histogram.begin());
  return (mode + 0.5) * bin - half_range;
}

/// The extent along the expected face of the board strip nearest the expected midpoint, from
/// the lateral positions of the points at cross-board height near the face depth. There a
/// pallet's face is one unbroken 800 mm strip, while its neighbours in the row are separate
/// strips (nothing stands at that height between pallets, and a side face only fills the bin at
/// its own edge), so the strip tells this pallet's points from theirs before any fit.
std::optional<std::pair<double, double>> board_strip(const std::vector<double>& laterals, double half_range,
                                                     double min_width) {
  constexpr double bin = 0.02;
  constexpr int max_gap_bins = 2;  // the cross board spans the 41 mm gaps between deck boards
  const int bins = static_cast<int>(std::ceil(2.0 * half_range / bin)) + 1;
  std::vector<int> count(bins, 0);
  for (double l : laterals) ++count[std::clamp(static_cast<int>((l + half_range) / bin), 0, bins - 1)];
  std::optional<std::pair<double, double>> best;
  for (int i = 0; i < bins;) {
    if (count[i] == 0) {
      ++i;
      continue;
    }
    int last = i;
    for (int j = i + 1; j < bins && j - last <= max_gap_bins + 1; ++j) {
      if (count[j] > 0) last = j;
    }
    const double lo = i * bin - half_range;
    const double hi = (last + 1) * bin - half_range;
    if (hi - lo >= min_width && (!best || std::abs(lo + hi) < std::abs(best->first + best->second))) {
      best = std::pair{lo, hi};
    }
    i = last + 1;
  }
  return best;
}

std::optional<FaceFit> fit_face(const std::vector<Sample>& samples, Vec3 origin, const FaceFrame& expected,
                                SearchExtent extent, double base_height, const PalletDetectorParams& params,
                                const std::optional<FaceFrame>& guess, std::pair<double, double> guess_span,
                                int& point_count) {
  std::vector<Vec2> all;
  std::vector<double> all_depths;
  std::vector<double> all_laterals;
  std::vector<bool> at_board_height;
  for (const Sample& s : samples) {
    if (std::isnan(s.depth)) continue;
    const Vec3 p = origin + s.depth * s.ray;
    const double h = p.z - base_height;
    if (h < params.scan_bottom || h > params.pallet.height - 0.015) continue;
    const Vec2 rel = xy(p) - expected.point;
    const double d = geometry::dot(rel, expected.normal);
    const double lateral = geometry::dot(rel, expected.along);
    if (std::abs(lateral) > extent.lateral || std::abs(d) > extent.depth) continue;
    all.push_back(xy(p));
    all_depths.push_back(d);
    all_laterals.push_back(lateral);
    at_board_height.push_back(h > params.pallet.pocket_height);
  }
  const FaceFrame frame = guess.value_or(expected);
  std::pair<double, double> span = guess_span;
  if (!guess) {
    const double face_depth = densest_depth(all_depths, extent.depth);
    std::vector<double> board_laterals;
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (at_board_height[i] && std::abs(all_depths[i] - face_depth) < extent.depth - params.roi_margin) {
        board_laterals.push_back(all_laterals[i]);
      }
    }
    const auto strip = board_strip(board_laterals, extent.lateral, 0.5 * params.pallet.width);
    span = strip ? std::pair{strip->first - 0.03, strip->second + 0.03} : std::pair{-extent.lateral, extent.lateral};
  }
  std::vector<Vec2> candidates;
  std::vector<double> depths;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const double s_along = geometry::dot(all[i] - frame.point, frame.along);
    if (s_along < span.first || s_along > span.second) continue;
    candidates.push_back(all[i]);
    depths.push_back(all_depths[i]);
  }
  point_count = static_cast<int>(candidates.size());
  if (point_count < params.min_face_points) return std::nullopt;
  std::vector<Vec2> inliers;
  if (guess) {
    for (Vec2 p : candidates) {
      if (std::abs(geometry::dot(p - guess->point, guess->normal)) < 0.05) inliers.push_back(p);
    }
  } else {
    const double mode_depth = densest_depth(depths, extent.depth);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (std::abs(depths[i] - mode_depth) < 0.12) inliers.push_back(candidates[i]);
    }
  }
  for (double tolerance : {0.08, 0.05, params.fit_inlier, params.fit_inlier}) {
    point_count = static_cast<int>(inliers.size());
    if (point_count < params.min_face_points) return std::nullopt;
    const FaceFrame face = fit_line(inliers, xy(origin));
    inliers.clear();
    for (Vec2 p : candidates) {
      if (std::abs(geometry::dot(p - face.point, face.normal)) < tolerance) inliers.push_back(p);
    }
  }
  point_count = static_cast<int>(inliers.size());
  if (point_count < params.min_face_points) return std::nullopt;
  return FaceFit{fit_line(inliers, xy(origin)), point_count};
}

/// A run of equal labels along the face, metres.
struct Run {
  bool face = false;
  double begin = 0.0;
  double end = 0.0;
  double width() const { return end - begin; }
};

/// One height slice of the rectified face: per bin along the face, pixels whose ray crosses the
/// face inside the slice, and how many of them return from the face itself.
struct Slice {
  double bottom = 0.0;
  double top = 0.0;
  std::vector<int> face;
  std::vector<int> total;
};

/// The slice's runs: a bin is face when at least half its pixels are; bins no pixel crossed
/// take their left neighbour's label.
std::vector<Run> runs_of(const Slice& slice, double s0, double bin) {
  std::vector<Run> runs;
  int label = -1;
  for (std::size_t i = 0; i < slice.total.size(); ++i) {
    if (slice.total[i] > 0) label = 2 * slice.face[i] >= slice.total[i] ? 1 : 0;
    if (label < 0) continue;
    const double begin = s0 + i * bin;
    if (runs.empty() || runs.back().face != (label == 1)) {
      runs.push_back({label == 1, begin, begin + bin});
    } else {
      runs.back().end = begin + bin;
    }
  }
  return runs;
}

/// Removes speckle: flips the narrowest interior run below `min_run` into its neighbours until
/// none is left.
void drop_noise_runs(std::vector<Run>& runs, double min_run) {
  while (runs.size() >= 3) {
    std::size_t narrowest = 0;
    for (std::size_t i = 1; i + 1 < runs.size(); ++i) {
      if (narrowest == 0 || runs[i].width() < runs[narrowest].width()) narrowest = i;
    }
    if (narrowest == 0 || runs[narrowest].width() >= min_run) return;
    runs[narrowest - 1].end = runs[narrowest + 1].end;
    runs.erase(runs.begin() + static_cast<std::ptrdiff_t>(narrowest),
               runs.begin() + static_cast<std::ptrdiff_t>(narrowest) + 2);
  }
}

struct Match {
  int features = 0;
  std::array<double, 6> edges{};  ///< outer left, ..., outer right, metres along the face
  double centre() const { return (edges[0] + edges[5] + edges[1] + edges[4] + edges[2] + edges[3]) / 6.0; }
};

/// Scans a slice's runs left to right for column, pocket, column, pocket, column with the
/// expected widths, stopping at the sixth feature [Stacker thesis, section 6.2.2]. Every start
/// is tried and the full match nearest the expected midpoint wins, so a neighbouring pallet in
/// the row does not capture the scan.
Match match_slice(const std::vector<Run>& runs, const PalletFaceModel& model, double tolerance, double s_expected) {
  const double widths[5] = {model.outer_column, model.pocket, model.middle_column, model.pocket, model.outer_column};
  Match best;
  double best_offset = 1e9;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!runs[i].face) continue;
    Match m;
    for (std::size_t k = 0; k < 5 && i + k < runs.size(); ++k) {
      if (std::abs(runs[i + k].width() - widths[k]) > tolerance) break;
      m.features = k == 0 ? 2 : m.features + 1;
    }
    if (m.features < 6) {
      if (m.features > best.features && best.features < 6) best = m;
      continue;
    }
    m.edges = {runs[i].begin, runs[i].end, runs[i + 2].begin, runs[i + 2].end, runs[i + 4].begin, runs[i + 4].end};
    const double offset = std::abs(m.centre() - s_expected);
    if (best.features < 6 || offset < best_offset) {
      best = m;
      best_offset = offset;
    }
  }
  return best;
}

/// Segments the region of interest against the fitted face and fills the height slices. A
/// pixel is face when its return lies within `face_band`, along its ray, of where the ray
/// crosses the face; it is placed at that crossing, which is exact whatever the range noise, so
/// noise only flips labels and never moves an edge [the thesis segments by a fixed depth range,
/// section 6.2.1, which from a camera looking down also keeps the floor in front].
std::vector<Slice> scan_slices(const std::vector<Sample>& samples, Vec3 origin, const FaceFrame& face, double s0,
                               double bin, int bins, double base_height, const PalletDetectorParams& params) {
  std::vector<Slice> slices(std::max(params.scan_slices, 1));
  const double thickness = 2.0 * (params.scan_top - params.scan_bottom) / (slices.size() + 1);
  for (std::size_t k = 0; k < slices.size(); ++k) {
    slices[k].bottom = params.scan_bottom + 0.5 * thickness * k;
    slices[k].top = slices[k].bottom + thickness;
    slices[k].face.assign(bins, 0);
    slices[k].total.assign(bins, 0);
  }
  const double face_offset = geometry::dot(face.point - xy(origin), face.normal);
  for (const Sample& s : samples) {
    const double approach = geometry::dot(xy(s.ray), face.normal);
    if (approach > -1e-9) continue;  // the ray never reaches the face
    const double lambda = face_offset / approach;
    if (lambda <= 0.0) continue;
    const double h = origin.z + lambda * s.ray.z - base_height;
    if (h < params.scan_bottom || h > params.scan_top) continue;
    const Vec2 crossing = xy(origin) + lambda * xy(s.ray);
    const int b = static_cast<int>(std::floor((geometry::dot(crossing - face.point, face.along) - s0) / bin));
    if (b < 0 || b >= bins) continue;
    const bool on_face = !std::isnan(s.depth) && std::abs(s.depth - lambda) * norm(s.ray) < params.face_band;
    for (Slice& slice : slices) {
      if (h < slice.bottom || h > slice.top) continue;
      ++slice.total[b];
      if (on_face) ++slice.face[b];
    }
  }
  return slices;
}

/// The pattern found along one fitted face: the most features any slice matched and, when some
/// slices matched all six, their averaged edges (metres along `face`).
struct FaceScan {
  int features = 0;
  int slices = 0;
  std::array<double, 6> edges{};
  double midpoint() const { return (edges[0] + edges[1] + edges[2] + edges[3] + edges[4] + edges[5]) / 6.0; }
};

FaceScan scan_face(const std::vector<Sample>& samples, Vec3 origin, const FaceFrame& face, const FaceFrame& roi_face,
                   SearchExtent extent, double base_height, const DepthCameraModel& camera,
                   const PalletDetectorParams& params) {
  // Bins along the face about one pixel's footprint wide, over the searched width.
  const Vec3 face_centre{face.point.x, face.point.y, base_height + 0.06};
  const double bin = std::clamp(norm(face_centre - origin) * camera.pixel_angle(), 0.005, 0.03);
  const double s_expected = geometry::dot(roi_face.point - face.point, face.along);
  const double s0 = s_expected - extent.lateral;
  const int bins = static_cast<int>(std::ceil(2.0 * extent.lateral / bin));
  const std::vector<Slice> slices = scan_slices(samples, origin, face, s0, bin, bins, base_height, params);

  // Bottom to top, one match per slice.
  FaceScan scan;
  std::vector<Match> full;
  for (const Slice& slice : slices) {
    std::vector<Run> runs = runs_of(slice, s0, bin);
    drop_noise_runs(runs, params.min_run);
    const Match m = match_slice(runs, params.pallet, params.width_tolerance + bin, s_expected);
    scan.features = std::max(scan.features, m.features);
    if (m.features == 6) full.push_back(m);
  }
  if (full.empty()) return scan;
  // Slices that disagree with the others (another pallet, a speckle pattern) are left out.
  std::vector<double> centres;
  for (const Match& m : full) centres.push_back(m.centre());
  std::nth_element(centres.begin(), centres.begin() + centres.size() / 2, centres.end());
  const double median = centres[centres.size() / 2];
  for (const Match& m : full) {
    if (std::abs(m.centre() - median) > 0.03) continue;
    ++scan.slices;
    for (int k = 0; k < 6; ++k) scan.edges[k] += m.edges[k];
  }
  for (double& e : scan.edges) e /= scan.slices;
  return scan;
}

}  // namespace

geometry::Pose2 Detection::pallet_pose(double length) const {
  const Vec2 c = midpoint - 0.5 * length * heading(yaw);
  return {c.x, c.y, yaw};
}

PixelWindow detection_window(const DepthCameraModel& camera, const PalletExpectation& expected,
                             const PalletDetectorParams& params) {
  const FaceFrame roi_face =
      facing_face(expected.roi_centre.value_or(expected.pallet), xy(camera_origin(camera)), 0.5 * params.pallet.length);
  return region_of_interest(camera, camera_axes(camera.mount), roi_face, search_extent(expected, params),
                            expected.base_height, params);
}

Detection detect_pallet(const DepthImage& image, const DepthCameraModel& camera, const PalletExpectation& expected,
                        const PalletDetectorParams& params) {
  Detection result;
  const CameraAxes axes = camera_axes(camera.mount);
  const Vec3 origin = camera_origin(camera);
  const double half_length = 0.5 * params.pallet.length;
  const FaceFrame target = facing_face(expected.pallet, xy(origin), half_length);
  const FaceFrame roi_face = facing_face(expected.roi_centre.value_or(expected.pallet), xy(origin), half_length);
  const SearchExtent extent = search_extent(expected, params);

  const PixelWindow roi = region_of_interest(camera, axes, roi_face, extent, expected.base_height, params);
  if (roi.empty()) {
    result.reason = "the expected pallet is outside the camera's field of view";
    return result;
  }
  const std::vector<Sample> samples = gather(image, camera, axes, roi);
  const double base = expected.base_height;
  auto fit = fit_face(samples, origin, roi_face, extent, base, params, std::nullopt, {}, result.face_points);
  if (!fit) {
    result.reason = "no pallet face in the region of interest (" + std::to_string(result.face_points) +
                    " depth points on a face, need " + std::to_string(params.min_face_points) + ")";
    return result;
  }
  FaceScan scan = scan_face(samples, origin, fit->face, roi_face, extent, base, camera, params);
  if (scan.slices > 0) {
    // Refit on this pallet's own face only, then scan again along the better line.
    int points = 0;
    const auto refit = fit_face(samples, origin, roi_face, extent, base, params, fit->face,
                                {scan.edges[0] - 0.03, scan.edges[5] + 0.03}, points);
    if (refit) {
      const FaceScan rescan = scan_face(samples, origin, refit->face, roi_face, extent, base, camera, params);
      if (rescan.slices > 0) {
        fit = refit;
        scan = rescan;
      }
    }
  }
  result.features = scan.features;
  result.face_points = fit->points;
  if (scan.features == 0) {
    result.reason = "no pallet-like transitions in the region of interest";
    return result;
  }
  if (scan.slices == 0) {
    result.reason = "only " + std::to_string(scan.features) + " of 6 features matched";
    return result;
  }
  // The midpoint is the centre of the middle block; the outer edges and the pockets are
  // symmetric about it too, so all six edges share the estimate.
  const double s_mid = scan.midpoint();
  result.slices = scan.slices;
  for (int k = 0; k < 6; ++k) result.edges[k] = scan.edges[k] - s_mid;
  result.midpoint = fit->face.point + s_mid * fit->face.along;
  result.yaw = std::atan2(fit->face.normal.y, fit->face.normal.x);

  // [Stacker thesis, section 6.3]: only detections inside the expected docking area count.
  const Vec2 offset = result.midpoint - target.point;
  const double lateral = geometry::dot(offset, target.along);
  const double depth = geometry::dot(offset, target.normal);
  const double yaw_error = geometry::angle_diff(result.yaw, std::atan2(target.normal.y, target.normal.x));
  if (std::abs(lateral) > expected.area.lateral_half) {
    result.reason = format("pallet outside the expected docking area: %.2f m sideways, the area allows %.2f m", lateral,
                           expected.area.lateral_half);
  } else if (std::abs(depth) > expected.area.depth_half) {
    result.reason = format("pallet outside the expected docking area: %.2f m in depth, the area allows %.2f m", depth,
                           expected.area.depth_half);
  } else if (std::abs(yaw_error) > expected.area.yaw_half) {
    result.reason = format("pallet outside the expected docking area: turned %.1f deg, the area allows %.1f deg",
                           yaw_error * 180.0 / std::numbers::pi, expected.area.yaw_half * 180.0 / std::numbers::pi);
  } else {
    result.found = true;
  }
  return result;
}

PalletTracker::PalletTracker(DepthCameraModel camera, PalletDetectorParams params, int max_misses)
    : camera_(camera), params_(params), max_misses_(max_misses) {}

void PalletTracker::set_target(const geometry::Pose2& pallet_in_map, double base_height, DockingArea area) {
  target_ = pallet_in_map;
  base_height_ = base_height;
  area_ = area;
  last_in_map_.reset();
  misses_ = 0;
}

Detection PalletTracker::update(const DepthImage& image, const geometry::Pose2& robot_in_map) {
  PalletExpectation expected;
  expected.pallet = geometry::map_pose_to_body(robot_in_map, target_);
  expected.base_height = base_height_;
  expected.area = area_;
  if (last_in_map_) expected.roi_centre = geometry::map_pose_to_body(robot_in_map, *last_in_map_);
  Detection d = detect_pallet(image, camera_, expected, params_);
  if (d.found) {
    last_in_map_ = geometry::body_pose_to_map(robot_in_map, d.pallet_pose(params_.pallet.length));
    misses_ = 0;
  } else if (++misses_ >= max_misses_) {
    last_in_map_.reset();
  }
  return d;
}

}  // namespace fleet::perception
