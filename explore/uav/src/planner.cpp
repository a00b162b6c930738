// The flight's map and planner (planner.hpp).
#include "parallax/uav/planner.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "parallax/uav/fly.hpp"

namespace parallax::uav {

LocalMap::LocalMap(const MapParams& p)
    : p_(p),
      slots_(std::size_t(p.size_cells) * std::size_t(p.size_cells)),
      frame_hits_(slots_.size(), 0),
      frame_cols_(slots_.size(), 0),
      frame_last_u_(slots_.size(), -1) {}

LocalMap::Slot* LocalMap::slot(int32_t ix, int32_t iz, bool create) {
  const int n = p_.size_cells;
  const int32_t cx = index(centre_x_m_), cz = index(centre_z_m_);
  if (std::abs(ix - cx) >= n / 2 || std::abs(iz - cz) >= n / 2) return nullptr;  // outside the window
  Slot& s = slots_[std::size_t(((iz % n) + n) % n) * std::size_t(n) + std::size_t(((ix % n) + n) % n)];
  if (s.ix != ix || s.iz != iz) {
    if (!create) return nullptr;
    s = Slot{ix, iz, 0, false};  // a cell that left the window is forgotten
  }
  return &s;
}

const LocalMap::Slot* LocalMap::slot(int32_t ix, int32_t iz) const {
  return const_cast<LocalMap*>(this)->slot(ix, iz, false);
}

LocalMap::Cell LocalMap::at(double x, double z) const {
  const Slot* s = slot(index(x), index(z));
  if (s == nullptr || !s->seen) return Cell::unknown;
  return s->log_odds >= p_.occupied_at ? Cell::occupied : Cell::free;
}

cv::Mat LocalMap::picture() const {
  const int n = p_.size_cells;
  cv::Mat img(n, n, CV_8UC3, cv::Scalar(128, 128, 128));
  const int32_t cx = index(centre_x_m_), cz = index(centre_z_m_);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t ix = cx - n / 2 + i, iz = cz + n / 2 - 1 - j;
      const Cell c = at((ix + 0.5) * p_.cell_m, (iz + 0.5) * p_.cell_m);
      if (c != Cell::unknown) img.at<cv::Vec3b>(j, i) = c == Cell::free ? cv::Vec3b(255, 255, 255) : cv::Vec3b(0, 0, 0);
    }
  cv::circle(img, cv::Point(n / 2, n / 2 - 1), 2, cv::Scalar(0, 0, 255), -1);
  return img;
}

void LocalMap::clear_disk(double x, double z, double r) {
  centre_x_m_ = x;
  centre_z_m_ = z;
  for (double dz = -r; dz <= r; dz += p_.cell_m)
    for (double dx = -r; dx <= r; dx += p_.cell_m)
      if (dx * dx + dz * dz <= r * r)
        if (Slot* s = slot(index(x + dx), index(z + dz), true)) {
          s->seen = true;
          s->log_odds = int16_t(std::max(int(s->log_odds) - p_.miss_loss, p_.log_odds_min));
        }
}

void LocalMap::integrate(const cv::Mat& disp, const cv::Mat& valid_in, const Rig& rig, const CameraPose& pose,
                         const cv::Mat& left, cv::Mat* hit_pixels) {
  if (hit_pixels != nullptr) *hit_pixels = cv::Mat::zeros(disp.size(), CV_8U);
  cv::Mat valid = valid_in;
  if (!left.empty() && p_.min_texture_grey > 0) {
    // Texture along the epipolar lines: a horizontal edge (the horizon, a wall's top) or a flat
    // region says nothing about disparity, however sharp it is.
    cv::Mat gx, texture;
    cv::Sobel(left, gx, CV_32F, 1, 0, 3, 0.25);
    cv::blur(cv::abs(gx), texture, cv::Size(5, 5));
    const cv::Mat textured = texture >= p_.min_texture_grey;
    valid = valid_in & textured;
  }
  centre_x_m_ = pose.position_m.x();
  centre_z_m_ = pose.position_m.z();
  const Eigen::Matrix3d axes = camera_axes(pose);
  const Eigen::Vector3d cam = pose.position_m;
  const double fb = rig.focal_px * rig.baseline_m, altitude = -cam.y();
  const int w = disp.cols, h = disp.rows;
  // Per column: the nearest hit's and the farthest trusted point's horizontal range.
  std::vector<double> nearest(std::size_t(w), 1e9), farthest(std::size_t(w), 0.0);
  std::vector<Slot*> touched;
  const int border = p_.border_px, top = std::max(border, p_.top_border_px);
  // Column by column, so that a cell knows how many columns hit it (frame_cols_).
  for (int u = border; u < w - border; ++u) {
    for (int v = top; v < h - border; ++v) {
      const float dp = disp.at<float>(v, u);
      // Not trusted: invalid, too small, or with its match outside the right image.
      if (valid.at<uint8_t>(v, u) == 0 || dp < p_.min_disparity_px || double(u) - dp < border) continue;
      const double z = fb / dp;
      const Eigen::Vector3d p =
          cam + axes * Eigen::Vector3d((u - rig.cx_px) * z / rig.focal_px, (v - rig.cy_px) * z / rig.focal_px, z);
      const double range = std::hypot(p.x() - cam.x(), p.z() - cam.z());
      if (range > p_.max_range_m) continue;
      farthest[std::size_t(u)] = std::max(farthest[std::size_t(u)], range);
      const bool in_band = std::fabs(-p.y() - altitude) <= p_.band_m;
      if (hit_pixels != nullptr) hit_pixels->at<uint8_t>(v, u) = in_band ? 255 : 128;
      if (!in_band) continue;
      nearest[std::size_t(u)] = std::min(nearest[std::size_t(u)], range);
      Slot* s = slot(index(p.x()), index(p.z()), true);
      if (s == nullptr) continue;
      const std::size_t i = std::size_t(s - slots_.data());
      if (frame_hits_[i]++ == 0) touched.push_back(s);
      if (frame_last_u_[i] != u) {
        frame_last_u_[i] = u;
        ++frame_cols_[i];
      }
    }
  }
  // A cell is hit when enough samples fall in it from enough of the columns it spans at its
  // range: an obstacle there fills them, a matcher's error patch (a few columns of wrong
  // disparities, scattered over ranges) does not.
  constexpr int32_t kHit = INT32_MAX / 2, kTouched = -2, kMissed = -1;
  for (Slot* s : touched) {
    const std::size_t i = std::size_t(s - slots_.data());
    const double dx = (s->ix + 0.5) * p_.cell_m - cam.x(), dz = (s->iz + 0.5) * p_.cell_m - cam.z();
    const double span_px = p_.cell_m / std::max(p_.cell_m, std::hypot(dx, dz)) * rig.focal_px;
    const bool hit = frame_hits_[i] >= p_.min_hits && frame_cols_[i] >= p_.min_column_fraction * span_px;
    frame_hits_[i] = hit ? kHit : kTouched;
    frame_cols_[i] = 0;
    frame_last_u_[i] = -1;
  }
  // Misses: each column's ray in the band, up to a cell before its nearest hit (or to its
  // farthest trusted point when it has none). What the matcher cannot see (a textureless wall)
  // stays unseen, and the planner keeps its margin from it.
  for (int u = border; u < w - border; u += 2) {
    const double free_m = std::min(nearest[std::size_t(u)] - 1.5 * p_.cell_m, farthest[std::size_t(u)]);
    if (free_m <= 0) continue;
    Eigen::Vector3d d = axes * Eigen::Vector3d((u - rig.cx_px) / rig.focal_px, 0, 1);
    d.y() = 0;
    d.normalize();
    for (double r = 0; r < free_m; r += 0.5 * p_.cell_m) {
      Slot* s = slot(index(cam.x() + r * d.x()), index(cam.z() + r * d.z()), true);
      if (s == nullptr) break;
      const std::size_t i = std::size_t(s - slots_.data());
      if (frame_hits_[i] == kHit || frame_hits_[i] == kMissed) continue;  // hit, or missed already this frame
      s->seen = true;
      s->log_odds = int16_t(std::max(int(s->log_odds) - p_.miss_loss, p_.log_odds_min));
      if (frame_hits_[i] == 0) touched.push_back(s);
      frame_hits_[i] = kMissed;
    }
  }
  for (Slot* s : touched) {
    int32_t& hits = frame_hits_[std::size_t(s - slots_.data())];
    if (hits == kHit) {
      s->seen = true;
      s->log_odds = int16_t(std::min(int(s->log_odds) + p_.hit_gain, p_.log_odds_max));
    }
    hits = 0;
  }
}

namespace {

// The map around a point as distances to the nearest occupied cell (capped just past the safety
// distance) and whether each cell was seen: what a path of the vehicle's width may not come near,
// and what it may not enter unseen.
class Clearance {
 public:
  Clearance(const LocalMap& map, const Eigen::Vector3d& centre, double radius_m, double safety_m, double unseen_m)
      : cell_(map.params().cell_m), cap_m_(safety_m + cell_) {
    const int reach = int(std::ceil(safety_m / cell_)) + 1;
    half_ = int(std::ceil(radius_m / cell_)) + reach + 1;
    n_ = 2 * half_ + 1;
    ix0_ = int32_t(std::floor(centre.x() / cell_)) - half_;
    iz0_ = int32_t(std::floor(centre.z() / cell_)) - half_;
    dist_.assign(std::size_t(n_) * std::size_t(n_), float(cap_m_));
    occupied_dist_ = dist_;
    seen_.assign(dist_.size(), 0);
    std::vector<LocalMap::Cell> cells(dist_.size());  // read once: the map's lookups are the cost
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) {
        const std::size_t k = std::size_t(j) * std::size_t(n_) + std::size_t(i);
        cells[k] = map.at((ix0_ + i + 0.5) * cell_, (iz0_ + j + 0.5) * cell_);
        seen_[k] = cells[k] != LocalMap::Cell::unknown ? 1 : 0;
      }
    // The distance of each offset within reach, once.
    const int side = 2 * reach + 1;
    std::vector<double> offset_m(std::size_t(side) * std::size_t(side));
    for (int b = -reach; b <= reach; ++b)
      for (int a = -reach; a <= reach; ++a)
        offset_m[std::size_t(b + reach) * std::size_t(side) + std::size_t(a + reach)] =
            std::sqrt(double(a * a + b * b)) * cell_;
    // Occupied cells keep a path safety_m away; unseen ones the vehicle's own radius (a
    // textureless wall is never occupied, only unseen).
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) {
        const LocalMap::Cell c = cells[std::size_t(j) * std::size_t(n_) + std::size_t(i)];
        if (c == LocalMap::Cell::free) continue;
        const bool occupied = c == LocalMap::Cell::occupied;
        // An unseen cell counts only where it borders a seen one (its inside is reached through it).
        if (!occupied && !borders_seen(i, j)) continue;
        const double grow = occupied ? 0.0 : safety_m - unseen_m;
        for (int b = -reach; b <= reach; ++b)
          for (int a = -reach; a <= reach; ++a) {
            const int x = i + a, y = j + b;
            if (x < 0 || y < 0 || x >= n_ || y >= n_) continue;
            const std::size_t k = std::size_t(y) * std::size_t(n_) + std::size_t(x);
            const double at_m = offset_m[std::size_t(b + reach) * std::size_t(side) + std::size_t(a + reach)];
            dist_[k] = std::min(dist_[k], float(at_m + grow));
            if (occupied) occupied_dist_[k] = std::min(occupied_dist_[k], float(at_m));
          }
      }
  }
  // Distance to the nearest occupied cell, capped at safety + a cell; 0 outside the window.
  double distance(double x, double z) const {
    const std::ptrdiff_t k = slot(x, z);
    return k < 0 ? 0.0 : double(dist_[std::size_t(k)]);
  }
  bool borders_seen(int i, int j) const {
    for (int b = -1; b <= 1; ++b)
      for (int a = -1; a <= 1; ++a) {
        const int x = i + a, y = j + b;
        if (x >= 0 && y >= 0 && x < n_ && y < n_ && seen_[std::size_t(y) * std::size_t(n_) + std::size_t(x)])
          return true;
      }
    return false;
  }
  bool unknown(double x, double z) const {
    const std::ptrdiff_t k = slot(x, z);
    return k < 0 || seen_[std::size_t(k)] == 0;
  }
  // The cost of the shortest path from each cell to the goal line z >= goal_z_m (metres; unseen
  // cells cost unseen_factor per metre: they may be free), keeping limit_m from occupied cells
  // and inside the bounds' margin. The window's edge is reached from the goal at the straight
  // distance to the goal line (the world beyond is unknown); infinity where no path exists. A
  // navigation function (a local planner's "navfn"): descending it leads round dead ends that a
  // direction search from the vehicle cannot see out of.
  // far_limit_m: the clearance kept farther than near_m from near_xz (a vehicle inside an
  // obstacle's margin may leave it at limit_m, but not take a gap narrower than far_limit_m on).
  void solve_cost_to_goal(double goal_z_m, double limit_m, double bound_half_width_m, double unseen_factor,
                          const Eigen::Vector2d& near_xz, double near_m, double far_limit_m) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    cost_.assign(dist_.size(), kInf);
    using Item = std::pair<float, int32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    // Which cells may be entered, once per solve (the search visits each cell's neighbours).
    std::vector<uint8_t> open_cell(dist_.size());
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) {
        const double x = (ix0_ + i + 0.5) * cell_, z = (iz0_ + j + 0.5) * cell_;
        const double need_m = std::hypot(x - near_xz.x(), z - near_xz.y()) <= near_m ? limit_m : far_limit_m;
        const std::size_t k = std::size_t(j) * std::size_t(n_) + std::size_t(i);
        open_cell[k] = std::fabs(x) <= bound_half_width_m && occupied_dist_[k] >= need_m ? 1 : 0;
      }
    auto passable = [&](int i, int j) { return open_cell[std::size_t(j) * std::size_t(n_) + std::size_t(i)] != 0; };
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) {
        const double z = (iz0_ + j + 0.5) * cell_;
        const bool edge = i == 0 || j == 0 || i == n_ - 1 || j == n_ - 1;
        if ((!edge && z < goal_z_m) || !passable(i, j)) continue;
        const int32_t k = j * n_ + i;
        cost_[std::size_t(k)] = float(std::max(0.0, goal_z_m - z));
        open.push({cost_[std::size_t(k)], k});
      }
    const float diagonal = float(std::sqrt(2.0) * cell_), straight = float(cell_);
    while (!open.empty()) {
      const auto [c, k] = open.top();
      open.pop();
      if (c > cost_[std::size_t(k)]) continue;
      const int i = k % n_, j = k / n_;
      for (int b = -1; b <= 1; ++b)
        for (int a = -1; a <= 1; ++a) {
          const int x = i + a, y = j + b;
          if ((a == 0 && b == 0) || x < 0 || y < 0 || x >= n_ || y >= n_ || !passable(x, y)) continue;
          const std::size_t kk = std::size_t(y) * std::size_t(n_) + std::size_t(x);
          const float step = (a != 0 && b != 0 ? diagonal : straight) * (seen_[kk] ? 1.0f : float(unseen_factor));
          if (c + step < cost_[kk]) {
            cost_[kk] = c + step;
            open.push({cost_[kk], int32_t(kk)});
          }
        }
    }
  }
  // Where the shortest path from a point is after length_m (down the cost, neighbour by
  // neighbour); the point itself when it has no path. Of the neighbours on a shortest path (an
  // 8-connected grid has many), the one nearest the goal's direction (+z): the straight line
  // rather than a staircase.
  Eigen::Vector2d follow_path(double x, double z, double length_m) const {
    std::ptrdiff_t k = slot(x, z);
    Eigen::Vector2d at(x, z);
    if (k < 0 || !std::isfinite(cost_[std::size_t(k)])) return at;
    for (double walked = 0; walked < length_m;) {
      const int i = int(k % n_), j = int(k / n_);
      std::ptrdiff_t next = k;
      double next_step = 0, next_rank = -1e9;
      for (int b = -1; b <= 1; ++b)
        for (int a = -1; a <= 1; ++a) {
          const int xi = i + a, yj = j + b;
          if ((a == 0 && b == 0) || xi < 0 || yj < 0 || xi >= n_ || yj >= n_) continue;
          const std::ptrdiff_t kk = std::ptrdiff_t(yj) * n_ + xi;
          const double step = (a != 0 && b != 0 ? std::sqrt(2.0) : 1.0) * cell_;
          const double descent = double(cost_[std::size_t(k)]) - double(cost_[std::size_t(kk)]);
          if (descent <= 0) continue;
          // Steepest first; among the equally steep, the most towards +z.
          const double rank = std::round(descent / step * 100.0) + 0.01 * b / std::hypot(a, b);
          if (rank > next_rank) {
            next_rank = rank;
            next = kk;
            next_step = step;
          }
        }
      if (next == k) break;  // the goal line or the window's edge
      walked += next_step;
      k = next;
      at = Eigen::Vector2d((ix0_ + int(k % n_) + 0.5) * cell_, (iz0_ + int(k / n_) + 0.5) * cell_);
    }
    return at;
  }
  // solve_cost_to_goal's cost at a point; infinity outside the window or where no path exists.
  double cost_to_goal(double x, double z) const {
    const std::ptrdiff_t k = slot(x, z);
    return k < 0 ? std::numeric_limits<double>::infinity() : double(cost_[std::size_t(k)]);
  }

 private:
  std::ptrdiff_t slot(double x, double z) const {
    const int i = int(std::floor(x / cell_)) - ix0_, j = int(std::floor(z / cell_)) - iz0_;
    if (i < 0 || j < 0 || i >= n_ || j >= n_) return -1;
    return std::ptrdiff_t(j) * n_ + i;
  }
  double cell_, cap_m_;
  int half_ = 0, n_ = 0;
  int32_t ix0_ = 0, iz0_ = 0;
  std::vector<float> dist_, occupied_dist_, cost_;
  std::vector<uint8_t> seen_;
};

// The free distance along a heading over a Clearance (Planner::free_distance). A path may not come
// nearer an obstacle than safety_m, or than where it starts when it starts nearer (so a vehicle
// inside the margin can still leave it).
double free_along(const Clearance& c, const PlannerParams& p, double cell_m, const Eigen::Vector3d& from,
                  double heading) {
  const double step = 0.5 * cell_m, sx = std::sin(heading), sz = std::cos(heading);
  const double limit = std::min(p.safety_m, c.distance(from.x(), from.z()) - 0.5 * cell_m);
  for (double r = step; r < p.horizon_m; r += step) {
    const double x = from.x() + r * sx, z = from.z() + r * sz;
    // The bounds' margin: not entered, nor gone deeper into (a vehicle braked into it may leave).
    if (std::fabs(x) > p.bound_half_width_m - p.safety_m && std::fabs(x) > std::fabs(from.x())) return r - step;
    if (c.distance(x, z) < limit) return std::max(0.0, r - 2 * step);
    if (r > 0.5 && c.unknown(x, z)) return r;
  }
  return p.horizon_m;
}

}  // namespace

double Planner::free_distance(const LocalMap& map, const Eigen::Vector3d& from, double heading) const {
  return free_along(Clearance(map, from, p_.horizon_m, p_.safety_m, p_.unseen_margin_m), p_, map.params().cell_m, from,
                    heading);
}

Plan Planner::plan(const LocalMap& map, const VehicleState& s) {
  const Eigen::Vector3d& pos = s.position_m;
  const double cell = map.params().cell_m;
  Clearance clear(map, pos, p_.horizon_m, p_.safety_m, p_.unseen_margin_m);
  const double goal_bearing = std::atan2(p_.goal_xz.x() - pos.x(), p_.goal_xz.y() - pos.z());
  // A path may come no nearer an obstacle than safety_m, or than the vehicle is now when nearer.
  const double limit = std::min(p_.safety_m, clear.distance(pos.x(), pos.z()) - 0.5 * cell);
  // Recovering from a stop: the route keeps the full safety distance beyond the vehicle's own
  // surroundings (no gap the rollouts will not fly), and the candidates cover the whole circle.
  const bool recovering = recovery_;
  const Eigen::Vector2d here(pos.x(), pos.z());
  clear.solve_cost_to_goal(p_.goal_xz.y(), limit, p_.bound_half_width_m - p_.safety_m + cell, p_.unseen_cost, here,
                           p_.safety_m + p_.recovery_near_m, recovering ? p_.safety_m : limit);
  const double cost_here = clear.cost_to_goal(pos.x(), pos.z());
  const bool routed = std::isfinite(cost_here);
  // How fast a course descends the cost to the goal (1: straight at it along the shortest path),
  // over the lookahead or as much of it as is passable; the goal's bearing when the vehicle has no
  // path (it is inside an obstacle's margin as mapped).
  auto progress = [&](double heading) {
    if (!routed) return std::cos(wrap_angle(heading - goal_bearing));
    for (double d = p_.lookahead_m; d > 0.5; d -= 1.0) {
      const double c = clear.cost_to_goal(pos.x() + d * std::sin(heading), pos.z() + d * std::cos(heading));
      if (std::isfinite(c)) return std::clamp((cost_here - c) / d, -1.0, 1.0);
    }
    return -1.0;
  };
  // The direction the shortest path leaves in: the candidates are centred on it, and a vehicle
  // that must stop looks there.
  double path_bearing = goal_bearing;
  if (routed) {
    const Eigen::Vector2d ahead = clear.follow_path(pos.x(), pos.z(), p_.lookahead_m);
    if ((ahead - Eigen::Vector2d(pos.x(), pos.z())).norm() > 0.5 * cell)
      path_bearing = std::atan2(ahead.x() - pos.x(), ahead.y() - pos.z());
  }
  auto speed_for = [&](double free_m) {
    return std::min(p_.cruise_mps, stopping_distance_speed_bound(p_.brake_mps2, p_.reaction_s,
                                                                 std::max(0.0, free_m - p_.stop_margin_m)));
  };
  // The vehicle's own response to a setpoint (the velocity loop's gain, acceleration and jerk
  // limits) for rollout_s, the setpoint held until the vehicle must brake to stop short of the
  // free distance (the plan a frame later would do no less) and zero after: safe when it never
  // comes nearer an obstacle than the safety distance (or than it is now, when nearer), nor enters
  // an unseen cell or the bounds' margin.
  auto safe = [&](double heading, double speed, double free_m) {
    VehicleState v = s;
    const Eigen::Vector3d dir(std::sin(heading), 0, std::cos(heading));
    const double stop_at_m = std::max(0.0, free_m - p_.stop_margin_m);
    constexpr double kDt = 0.05;
    bool stopping = false;
    for (double t = 0; t < p_.rollout_s; t += kDt) {
      const double along_mps = std::max(0.0, v.velocity_mps.dot(dir));
      const double to_stop_m = along_mps * (p_.reaction_s + along_mps / (2.0 * p_.brake_mps2));
      stopping = stopping || (v.position_m - pos).dot(dir) + to_stop_m >= stop_at_m;
      step_vehicle(v, stopping ? Eigen::Vector3d::Zero().eval() : (dir * speed).eval(), heading, p_.vehicle, kDt);
      const double x = v.position_m.x(), z = v.position_m.z();
      if (std::fabs(x) > p_.bound_half_width_m - p_.safety_m && std::fabs(x) > std::fabs(pos.x())) return false;
      if (clear.distance(x, z) < limit) return false;
      if ((v.position_m - pos).norm() > 0.5 && clear.unknown(x, z)) return false;
    }
    return true;
  };
  // A candidate's speed: what its free distance allows, halved until its rollout is safe; 0 when
  // even stopping while turning to it is not.
  auto checked_speed = [&](double heading, double free_m) {
    double v = speed_for(free_m);
    for (int tries = 0; tries < 3; ++tries, v *= 0.5)
      if (safe(heading, v, free_m)) return v;
    return safe(heading, 0.0, free_m) ? 0.0 : -1.0;
  };
  // Progress along the path to the goal at the checked speed, less a cost for a course that ends
  // short of the horizon (it will need a turn later: turning early is cheaper) and for changing
  // course.
  auto score = [&](double heading, double free_m, double speed) {
    if (speed < 0) return -1e9;
    return speed * progress(heading) - p_.short_cost * p_.cruise_mps * (1.0 - free_m / p_.horizon_m) -
           (has_heading_ ? p_.turn_cost * p_.cruise_mps * std::fabs(wrap_angle(heading - heading_)) : 0.0);
  };
  struct Choice {
    double heading = 0, free_m = 0, speed = -1, score = -1e18;
  } best, widest, flyable;
  widest.free_m = -1;
  const int n = int(std::round((recovering ? 180.0 : p_.span_deg) / p_.step_deg));
  for (int k = -n; k <= n; ++k) {
    Choice c;
    c.heading = wrap_angle(path_bearing + k * p_.step_deg * M_PI / 180.0);
    c.free_m = free_along(clear, p_, cell, pos, c.heading);
    c.speed = checked_speed(c.heading, c.free_m);
    c.score = score(c.heading, c.free_m, c.speed);
    if (c.score > best.score) best = c;
    if (c.speed >= 0 && c.free_m > widest.free_m) widest = c;
    if (c.speed >= 0.2 * p_.cruise_mps && c.score > flyable.score) flyable = c;
  }
  // Hysteresis: keep the current direction unless another is clearly better.
  if (has_heading_) {
    Choice c;
    c.heading = heading_;
    c.free_m = free_along(clear, p_, cell, pos, heading_);
    c.speed = checked_speed(heading_, c.free_m);
    c.score = score(heading_, c.free_m, c.speed);
    if (c.speed > 0.2 * p_.cruise_mps && c.score + p_.hysteresis * p_.cruise_mps >= best.score) best = c;
  }
  Plan plan;
  plan.braking = best.speed < 0.2 * p_.cruise_mps;
  // Nothing free enough: stop, turning to where the path leads (to see it), or without one to the
  // widest safe direction.
  Choice look;
  look.heading = path_bearing;
  look.free_m = free_along(clear, p_, cell, pos, path_bearing);
  const Choice& go = !plan.braking ? best : routed ? look : widest.free_m >= 0 ? widest : best;
  plan.velocity_mps = Eigen::Vector3d(std::sin(go.heading), 0, std::cos(go.heading)) * (plan.braking ? 0.0 : go.speed);
  plan.yaw_rad = go.heading;
  plan.heading_rad = go.heading;
  plan.free_m = go.free_m;
  recover(plan, s, flyable.speed > 0 ? flyable.heading : 0, flyable.speed, flyable.free_m);
  const double off = wrap_angle(plan.heading_rad - goal_bearing);
  const int side = off > 10 * M_PI / 180 ? 1 : off < -10 * M_PI / 180 ? -1 : 0;
  if (side != 0) {
    if (side_ != 0 && side != side_) ++flips_;
    side_ = side;
  }
  heading_ = plan.heading_rad;
  has_heading_ = true;
  return plan;
}

void Planner::recover(Plan& plan, const VehicleState& s, double flyable_heading, double flyable_mps,
                      double flyable_free_m) {
  const Eigen::Vector2d here(s.position_m.x(), s.position_m.z());
  stuck_plans_ = plan.braking && s.velocity_mps.norm() < p_.still_mps ? stuck_plans_ + 1 : 0;
  if (!recovery_ && stuck_plans_ >= p_.stuck_plans) {
    recovery_ = true;
    recovery_from_xz_ = here;
    scan_steps_ = 0;
    scan_yaw_ = s.yaw_rad;
    ++recoveries_;
  }
  if (!recovery_) return;
  if (!plan.braking) {
    if ((here - recovery_from_xz_).norm() > p_.recovery_m) recovery_ = false;
    return;
  }
  // Still stopped: turn on the spot a step at a time (what the cameras then see enters the map),
  // and after a whole turn fly the best direction that can be flown at all, away from the goal if
  // need be; with none, turn again.
  const int full_turn = int(std::ceil(360.0 / p_.scan_step_deg));
  if (scan_steps_ < full_turn) {
    if (std::fabs(wrap_angle(s.yaw_rad - scan_yaw_)) < 5.0 * M_PI / 180.0) {
      scan_yaw_ = wrap_angle(scan_yaw_ + p_.scan_step_deg * M_PI / 180.0);
      ++scan_steps_;
    }
    plan.yaw_rad = scan_yaw_;
  } else if (flyable_mps > 0) {
    plan.braking = false;
    plan.velocity_mps = Eigen::Vector3d(std::sin(flyable_heading), 0, std::cos(flyable_heading)) * flyable_mps;
    plan.yaw_rad = plan.heading_rad = flyable_heading;
    plan.free_m = flyable_free_m;
  } else {
    scan_steps_ = 0;
  }
}

}  // namespace parallax::uav
