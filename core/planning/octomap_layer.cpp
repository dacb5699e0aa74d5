#include "planning/octomap_layer.hpp"

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fleet::planning {

using geometry::Vec2;

namespace {

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();

std::uint32_t pack(std::uint16_t kx, std::uint16_t ky) {
  return (static_cast<std::uint32_t>(kx) << 16) | ky;
}

}  // namespace

OctoMapLayer::OctoMapLayer(const OctoMapConfiguration& c)
    : configuration_(c),
      tree_(std::make_unique<octomap::OcTree>(c.resolution)),
      sensed_(c.area, c.projection_resolution, OccupancyGrid::kFree) {
  auto probability = [](double p, const char* key) {
    if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument(std::string("octomap layer: ") + key + " must be in (0, 1)");
  };
  probability(c.prob_hit, "prob_hit");
  probability(c.prob_miss, "prob_miss");
  probability(c.clamp_min, "clamp_min");
  probability(c.clamp_max, "clamp_max");
  probability(c.occupancy_threshold, "occupancy_threshold");
  if (!(c.prob_hit > 0.5) || !(c.prob_miss < 0.5)) {
    throw std::invalid_argument("octomap layer: prob_hit must exceed 0.5 and prob_miss stay below it");
  }
  tree_->setProbHit(c.prob_hit);
  tree_->setProbMiss(c.prob_miss);
  tree_->setClampingThresMin(c.clamp_min);
  tree_->setClampingThresMax(c.clamp_max);
  tree_->setOccupancyThres(c.occupancy_threshold);
  // Read the thresholds back as the tree stores them, so the early-abort comparisons below agree
  // bit for bit with the tree's own clamping.
  hit_ = tree_->getProbHitLog();
  miss_ = tree_->getProbMissLog();
  clamp_min_ = tree_->getClampingThresMinLog();
  clamp_max_ = tree_->getClampingThresMaxLog();
  threshold_ = tree_->getOccupancyThresLog();
  kz_ = tree_->coordToKey(c.scan_height);
  kx0_ = tree_->coordToKey(c.area.min_x);
  ky0_ = tree_->coordToKey(c.area.min_y);
  mirror_w_ = tree_->coordToKey(c.area.max_x) - kx0_ + 1;
  mirror_h_ = tree_->coordToKey(c.area.max_y) - ky0_ + 1;
  mirror_.assign(static_cast<std::size_t>(mirror_w_) * mirror_h_, kUnknown);
  clamped_free_.assign((mirror_.size() + 63) / 64, 0);
  occupied_leaves_.assign(sensed_.size(), 0);
}

OctoMapLayer::~OctoMapLayer() = default;

void OctoMapLayer::assume_free() {
  for (int my = 0; my < mirror_h_; ++my) {
    for (int mx = 0; mx < mirror_w_; ++mx) {
      if (!std::isnan(mirror_[static_cast<std::size_t>(my) * mirror_w_ + mx])) continue;
      set_leaf(static_cast<std::uint16_t>(kx0_ + mx), static_cast<std::uint16_t>(ky0_ + my), clamp_min_);
    }
  }
}

void OctoMapLayer::record(std::uint16_t kx, std::uint16_t ky, float before, float after) {
  const bool was = !std::isnan(before) && before >= threshold_;
  const bool is = after >= threshold_;
  if (was == is) return;
  const CellIndex c = sensed_.cell_of({tree_->keyToCoord(kx), tree_->keyToCoord(ky)});
  if (!sensed_.in_bounds(c.x, c.y)) return;
  const std::size_t i = sensed_.index(c.x, c.y);
  if (is) {
    if (occupied_leaves_[i]++ == 0) sensed_.cells()[i] = OccupancyGrid::kOccupied;
  } else if (occupied_leaves_[i] > 0 && --occupied_leaves_[i] == 0) {
    sensed_.cells()[i] = OccupancyGrid::kFree;
  }
}

void OctoMapLayer::apply(std::uint16_t kx, std::uint16_t ky, bool hit) {
  const int mx = kx - kx0_;
  const int my = ky - ky0_;
  if (mx < 0 || my < 0 || mx >= mirror_w_ || my >= mirror_h_) return;  // outside the site
  const std::size_t i = static_cast<std::size_t>(my) * mirror_w_ + mx;
  // A clamped leaf cannot move further the same way (the tree's own early abort, without the search).
  if (!hit && ((clamped_free_[i >> 6] >> (i & 63)) & 1u) != 0) return;
  float& m = mirror_[i];
  if (hit && m >= clamp_max_) return;
  const float before = m;
  const octomap::OcTreeNode* node = tree_->updateNode(octomap::OcTreeKey(kx, ky, kz_), hit ? hit_ : miss_, true);
  m = node->getLogOdds();
  note_leaf(i, m);
  record(kx, ky, before, m);
}

void OctoMapLayer::set_leaf(std::uint16_t kx, std::uint16_t ky, float log_odds) {
  const int mx = kx - kx0_;
  const int my = ky - ky0_;
  if (mx < 0 || my < 0 || mx >= mirror_w_ || my >= mirror_h_) return;
  const std::size_t i = static_cast<std::size_t>(my) * mirror_w_ + mx;
  float& m = mirror_[i];
  const float before = m;
  const octomap::OcTreeNode* node = tree_->setNodeValue(octomap::OcTreeKey(kx, ky, kz_), log_odds, true);
  m = node->getLogOdds();
  note_leaf(i, m);
  record(kx, ky, before, m);
}

void OctoMapLayer::insert_scan(const LidarScan& scan) {
  const double res = configuration_.resolution;
  const double inv = 1.0 / res;
  const int half = static_cast<int>(std::ceil(scan.max_range * inv)) + 2;
  // Which cells of the square around the sensor this scan has marked, one bit each: small enough
  // to stay in the cache while the beams are traced, and cleared for each scan.
  window_size_ = 2 * half + 1;
  const std::size_t words = (static_cast<std::size_t>(window_size_) * window_size_ + 63) / 64;
  marked_free_.assign(words, 0);
  marked_hit_.assign(words, 0);
  // Continuous key coordinates: key = floor(u), as OcTreeBaseImpl::coordToKey does.
  const double ox = scan.pose.x * inv + 32768.0;
  const double oy = scan.pose.y * inv + 32768.0;
  const int okx = static_cast<int>(std::floor(ox));
  const int oky = static_cast<int>(std::floor(oy));
  auto slot = [&](int kx, int ky) {
    return static_cast<std::size_t>(ky - oky + half) * window_size_ + (kx - okx + half);
  };
  auto marked = [](const std::vector<std::uint64_t>& bits, std::size_t i) { return (bits[i >> 6] >> (i & 63)) & 1u; };
  auto mark = [](std::vector<std::uint64_t>& bits, std::size_t i) { bits[i >> 6] |= std::uint64_t{1} << (i & 63); };
  hit_keys_.clear();
  const std::size_t n = scan.ranges.size();
  ends_.resize(n);
  has_hit_.resize(n);
  auto& ends = ends_;
  auto& has_hit = has_hit_;
  // Pass 1: endpoints. A cell with a hit is not also updated as free in the same scan (OctoMap's
  // computeUpdate gives occupied precedence the same way).
  for (std::size_t i = 0; i < n; ++i) {
    const double a = scan.pose.yaw + scan.angle_min + static_cast<double>(i) * scan.angle_increment;
    const bool hit = std::isfinite(scan.ranges[i]) && scan.ranges[i] <= scan.max_range;
    const double r = hit ? scan.ranges[i] : scan.max_range;
    ends[i] = {ox + r * inv * std::cos(a), oy + r * inv * std::sin(a)};
    has_hit[i] = hit ? 1 : 0;
    if (hit) {
      const int kx = static_cast<int>(std::floor(ends[i].first));
      const int ky = static_cast<int>(std::floor(ends[i].second));
      const std::size_t at = slot(kx, ky);
      if (!marked(marked_hit_, at)) {
        mark(marked_hit_, at);
        hit_keys_.push_back(pack(static_cast<std::uint16_t>(kx), static_cast<std::uint16_t>(ky)));
      }
    }
  }
  // Pass 2: the cells each beam passes before its endpoint (Amanatides and Woo in key space). From
  // a sensor on the site, a beam that has left the site's rectangle never comes back: the rest of
  // it is not traced (apply() would drop those cells).
  const bool origin_on_site = okx >= kx0_ && oky >= ky0_ && okx < kx0_ + mirror_w_ && oky < ky0_ + mirror_h_;
  const auto off_site = [&](int kx, int ky) {
    return origin_on_site && (kx < kx0_ || ky < ky0_ || kx >= kx0_ + mirror_w_ || ky >= ky0_ + mirror_h_);
  };
  // A cell seen free is updated at once (apply() skips one already as free as the tree lets it be
  // without a search of the tree, and cells off the site).
  const auto see_free = [&](int kx, int ky) {
    const std::size_t at = slot(kx, ky);
    if (marked(marked_hit_, at) || marked(marked_free_, at)) return;
    mark(marked_free_, at);
    apply(static_cast<std::uint16_t>(kx), static_cast<std::uint16_t>(ky), false);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const double ex = ends[i].first;
    const double ey = ends[i].second;
    int kx = okx;
    int ky = oky;
    const int ekx = static_cast<int>(std::floor(ex));
    const int eky = static_cast<int>(std::floor(ey));
    const double dx = ex - ox;
    const double dy = ey - oy;
    const int sx = dx > 0 ? 1 : -1;
    const int sy = dy > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double tdx = dx != 0.0 ? 1.0 / std::abs(dx) : inf;
    const double tdy = dy != 0.0 ? 1.0 / std::abs(dy) : inf;
    double tx = dx != 0.0 ? (sx > 0 ? (kx + 1 - ox) : (ox - kx)) * tdx : inf;
    double ty = dy != 0.0 ? (sy > 0 ? (ky + 1 - oy) : (oy - ky)) * tdy : inf;
    const int steps = std::abs(ekx - kx) + std::abs(eky - ky);
    bool left_site = false;
    for (int k = 0; k < steps && (kx != ekx || ky != eky); ++k) {
      if (off_site(kx, ky)) {
        left_site = true;
        break;
      }
      see_free(kx, ky);
      if (tx < ty) {
        kx += sx;
        tx += tdx;
      } else {
        ky += sy;
        ty += tdy;
      }
    }
    if (!has_hit[i] && !left_site && kx == ekx && ky == eky) {
      // No return: the last cell within range was seen free too.
      see_free(kx, ky);
    }
  }
  for (std::uint32_t k : hit_keys_)
    apply(static_cast<std::uint16_t>(k >> 16), static_cast<std::uint16_t>(k & 0xffff), true);
}

void OctoMapLayer::insert_grid(const OccupancyGrid& grid) {
  // Every leaf whose centre lies in a grid cell takes that cell's value, clamped.
  const double res = configuration_.resolution;
  const geometry::Bounds b = grid.bounds();
  const std::uint16_t x0 = tree_->coordToKey(b.min_x + res / 2);
  const std::uint16_t x1 = tree_->coordToKey(b.max_x - res / 2);
  const std::uint16_t y0 = tree_->coordToKey(b.min_y + res / 2);
  const std::uint16_t y1 = tree_->coordToKey(b.max_y - res / 2);
  for (int ky = y0; ky <= y1; ++ky) {
    for (int kx = x0; kx <= x1; ++kx) {
      const Vec2 c{tree_->keyToCoord(static_cast<std::uint16_t>(kx)),
                   tree_->keyToCoord(static_cast<std::uint16_t>(ky))};
      const CellIndex cell = grid.cell_of(c);
      if (!grid.in_bounds(cell.x, cell.y)) continue;
      set_leaf(static_cast<std::uint16_t>(kx), static_cast<std::uint16_t>(ky),
               grid.occupied(cell.x, cell.y) ? clamp_max_ : clamp_min_);
    }
  }
}

void OctoMapLayer::project(OccupancyGrid& out) const {
  const geometry::Bounds b = out.bounds();
  const double z = configuration_.scan_height;
  const double res = configuration_.resolution;
  const octomap::point3d lo(static_cast<float>(b.min_x), static_cast<float>(b.min_y), static_cast<float>(z - res / 2));
  const octomap::point3d hi(static_cast<float>(b.max_x), static_cast<float>(b.max_y), static_cast<float>(z + res / 2));
  for (auto it = tree_->begin_leafs_bbx(lo, hi), end = tree_->end_leafs_bbx(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    if (it.getDepth() == tree_->getTreeDepth()) {
      const CellIndex c = out.cell_of({it.getX(), it.getY()});
      out.set(c.x, c.y, true);
    } else {
      // A pruned (coarser) leaf covers several cells: mark its whole square.
      const double h = it.getSize() / 2.0;
      const CellIndex c0 = out.cell_of({it.getX() - h + res / 2, it.getY() - h + res / 2});
      const CellIndex c1 = out.cell_of({it.getX() + h - res / 2, it.getY() + h - res / 2});
      for (int y = c0.y; y <= c1.y; ++y)
        for (int x = c0.x; x <= c1.x; ++x) out.set(x, y, true);
    }
  }
}

int OctoMapLayer::leaf_state(Vec2 p) const {
  const octomap::OcTreeNode* node = tree_->search(p.x, p.y, configuration_.scan_height);
  if (node == nullptr) return -1;
  return tree_->isNodeOccupied(node) ? 1 : 0;
}

std::size_t OctoMapLayer::leaf_count() const {
  return tree_->getNumLeafNodes();
}

}  // namespace fleet::planning
