// The stereo renderer of synthetic scenes (scene.hpp): ray casting by primitive. Every primitive
// (trunk, box, branch) is intersected only over its image-space bounding box with a depth buffer,
// the ground analytically per pixel, so a frame costs about one ground hit and one shading per
// pixel plus the primitives' screen area; pixels on object edges get four samples.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "parallax/uav/scene.hpp"

namespace parallax::uav {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSkyGrey = 200.0;
constexpr double kNearM = 0.05;

// Seeded value noise on a 2D surface parameter, four octaves (periods 1/4 to 1/32 of a unit, each
// 3/4 of the coarser one's amplitude): grey levels 25..230. Lattice
// values come from a fixed 1024-entry permutation and value table offset by the seed (a Perlin-
// style hash: two table reads per lattice point, periodic over 1024 lattice cells). An octave
// whose period nears the pixel's footprint fades to its mean (octave_weight), so distant and
// grazing texture does not alias; footprint 0 keeps every octave.
constexpr int kLattice = 1024;
struct NoiseTables {
  uint16_t perm[kLattice];
  float value[kLattice];
  NoiseTables() {
    std::mt19937 rng(0x9E3779B9u);
    for (int i = 0; i < kLattice; ++i) perm[i] = uint16_t(i);
    std::shuffle(perm, perm + kLattice, rng);
    for (float& v : value) v = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
  }
};
const NoiseTables& tables() {
  static const NoiseTables t;
  return t;
}
float lattice(const NoiseTables& t, uint32_t seed, int64_t i, int64_t j) {
  const uint32_t a = t.perm[(uint32_t(i) + seed) & (kLattice - 1)];
  return t.value[(t.perm[(a + uint32_t(j) + (seed >> 10)) & (kLattice - 1)] + (seed >> 20)) & (kLattice - 1)];
}
// An octave's contrast after the pixel's box filter, roughly: whole down to a period of three
// footprints, 0.8 at two (the sampling limit), none at one (sinc(1/3) = 0.83, sinc(1/2) = 0.64,
// sinc(1) = 0; the sharper knee keeps less alias).
double octave_weight(double footprint, double freq) {
  return std::clamp(1.6 * (1.0 - footprint * freq), 0.0, 1.0);
}
double noise(uint32_t seed, double u, double v, double footprint) {
  const NoiseTables& t = tables();
  constexpr int kOctaves = 4;
  constexpr double kFalloff = 0.75;  // each octave's amplitude against the next coarser one's
  double sum = 0, norm = 0, amp = 1.0, freq = 4.0;
  // Unrolled: amp, freq and norm become constants.
#pragma GCC unroll 4
  for (uint32_t o = 0; o < kOctaves; ++o, norm += amp, amp *= kFalloff, freq *= 2.0) {
    const double w = octave_weight(footprint, freq);
    if (w <= 0) {
      sum += amp * 0.5;
      continue;
    }
    const double x = u * freq, y = v * freq;
    const double fi = std::floor(x), fj = std::floor(y);
    const int64_t i = int64_t(fi), j = int64_t(fj);
    const double fx = x - fi, fy = y - fj;
    const uint32_t s = seed * 0x2545F491u + o * 0x9E3779B9u;
    // Neighbouring pixels mostly fall in the same lattice cell: its corners are kept per octave.
    thread_local struct Cell {
      uint32_t s = 0;
      int64_t i = 0, j = 0;
      bool set = false;
      double a = 0, b = 0, c = 0, d = 0;
    } cache[kOctaves];
    Cell& k = cache[o];
    if (!k.set || k.s != s || k.i != i || k.j != j)
      k = {s,
           i,
           j,
           true,
           lattice(t, s, i, j),
           lattice(t, s, i + 1, j),
           lattice(t, s, i, j + 1),
           lattice(t, s, i + 1, j + 1)};
    sum += amp * (w * ((k.a * (1 - fx) + k.b * fx) * (1 - fy) + (k.c * (1 - fx) + k.d * fx) * fy) + (1 - w) * 0.5);
  }
  return std::clamp(127.5 + (sum / norm - 0.5) * 246.0, 25.0, 230.0);
}

// std::lround(std::clamp(g, 0, 255)) without the library call: for g >= 0.5, g + 0.5 is exact
// or rounds within [n, n + 1) of the true sum's integer part n (the sum cannot reach the next
// integer), so its truncation is lround's half-away-from-zero rounding; below 0.5 both give 0.
uint8_t round_grey(double g) {
  const double c = std::clamp(g, 0.0, 255.0);
  // The check's failing case (just below 0.5) is the select that gives 0. The sum is converted
  // first, so a loop of these is a select, not a branch, and vectorises.
  // NOLINTNEXTLINE(bugprone-incorrect-roundings)
  const int r = int(c + 0.5);
  return c < 0.5 ? uint8_t(0) : uint8_t(r);
}
// std::lround(x) for |x| < 2^62 by the same argument, mirrored for negative x.
long round_half_away(double x) {
  const double a = std::fabs(x);
  // NOLINTNEXTLINE(bugprone-incorrect-roundings)
  const long r = a < 0.5 ? 0L : long(a + 0.5);
  return x < 0 ? -r : r;
}

// atan2 to within 1e-5 rad (a minimax polynomial on [0, 1] and the octant's symmetries): texture
// coordinates need no more.
double fast_atan2(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y), mx = std::max(ax, ay);
  if (mx == 0) return 0;
  const double a = std::min(ax, ay) / mx, s = a * a;
  double r =
      ((((-0.0117212 * s + 0.05265332) * s - 0.11643287) * s + 0.19354346) * s - 0.33262347) * s * a + 0.99997726 * a;
  if (ay > ax) r = M_PI_2 - r;
  if (x < 0) r = M_PI - r;
  return y < 0 ? -r : r;
}

// A surface's grey level at surface coordinates (s, t) in metres.
double paint(const Scene& sc, Surface kind, uint32_t seed, double s, double t, double footprint_m, double scale,
             int face) {
  switch (kind) {
    case Surface::plain:
      return face == 0 ? 150.0 : 125.0;  // one grey per face orientation: edges, no texture
    case Surface::stripes: {
      const double amp = 70.0 * octave_weight(footprint_m, 1.0 / sc.stripe_period_m);
      return 128.0 + amp * std::sin(2.0 * M_PI * s / sc.stripe_period_m);
    }
    case Surface::textured:
    default:
      return noise(seed, s * scale, t * scale, footprint_m * scale);
  }
}

// Primitive ids in the depth buffer: 0 sky, 1 ground, then cylinders, boxes, branches.
struct Ids {
  int cylinders, boxes, branches;
  explicit Ids(const Scene& sc)
      : cylinders(2), boxes(2 + int(sc.cylinders.size())), branches(2 + int(sc.cylinders.size() + sc.boxes.size())) {}
};

double hit_ground(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  if (d.y() <= 1e-12) return kInf;
  const double t = -o.y() / d.y();
  return t > 0 ? t : kInf;
}

double hit_cylinder(const Cylinder& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const double ox = o.x() - c.x_m, oz = o.z() - c.z_m;
  const double a = d.x() * d.x() + d.z() * d.z(), b = 2 * (ox * d.x() + oz * d.z()),
               cc = ox * ox + oz * oz - c.radius_m * c.radius_m;
  const double disc = b * b - 4 * a * cc;
  if (a < 1e-12 || disc < 0) return kInf;
  const double t = (-b - std::sqrt(disc)) / (2 * a);
  if (t <= 0) return kInf;
  const double y = o.y() + t * d.y();
  return y < -c.height_m || y > 0 ? kInf : t;
}

// Slab test; `axis` is the axis of the entry face. The three slabs are intersected without early
// exits (the entry distance only grows and the exit distance only shrinks, so an empty interval at
// any step is an empty one at the end): the six divisions are independent.
double hit_box(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, int& axis) {
  const double lo[3] = {b.x0_m, -b.height_m, b.z0_m}, hi[3] = {b.x1_m, 0.0, b.z1_m};
  double t0 = 0, t1 = kInf;
  bool outside = false;
  axis = -1;
  for (int i = 0; i < 3; ++i) {
    // A ray parallel to the slab misses it from outside and is unbounded by it from inside.
    const bool parallel = std::fabs(d[i]) < 1e-12;
    outside = outside || (parallel && (o[i] < lo[i] || o[i] > hi[i]));
    const double ta = (lo[i] - o[i]) / d[i], tb = (hi[i] - o[i]) / d[i];
    const double enter = parallel ? -kInf : std::min(ta, tb), leave = parallel ? kInf : std::max(ta, tb);
    if (enter > t0) {
      t0 = enter;
      axis = i;
    }
    t1 = std::min(t1, leave);
  }
  return outside || t0 > t1 || axis < 0 || t0 <= 0 ? kInf : t0;
}

Eigen::Vector3d branch_axis(const Branch& br) {
  return {std::sin(br.heading_rad), 0.0, std::cos(br.heading_rad)};
}
Eigen::Vector3d branch_root(const Branch& br) {
  return {br.x_m, -br.height_m, br.z_m};
}

// What a branch's ray test needs of the ray's origin o alone: the axis, o from the root, and its
// part across the axis.
struct BranchFromOrigin {
  Eigen::Vector3d ax, w, ww;
  double c;
  BranchFromOrigin(const Branch& br, const Eigen::Vector3d& o)
      : ax(branch_axis(br)),
        w(o - branch_root(br)),
        ww(w - w.dot(ax) * ax),
        c(ww.squaredNorm() - br.radius_m * br.radius_m) {}
};

// A finite cylinder around the branch's axis (its caps are too small to matter), for rays from the
// origin `from` was made for.
double hit_branch(const Branch& br, const BranchFromOrigin& from, const Eigen::Vector3d& d) {
  const Eigen::Vector3d& ax = from.ax;
  const Eigen::Vector3d& w = from.w;
  const Eigen::Vector3d dd = d - d.dot(ax) * ax;
  const double a = dd.squaredNorm(), b = 2 * dd.dot(from.ww), c = from.c;
  const double disc = b * b - 4 * a * c;
  if (a < 1e-12 || disc < 0) return kInf;
  const double t = (-b - std::sqrt(disc)) / (2 * a);
  if (t <= 0) return kInf;
  const double s = (w + t * d).dot(ax);
  return s < 0 || s > br.length_m ? kInf : t;
}
double hit_branch(const Branch& br, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  return hit_branch(br, BranchFromOrigin(br, o), d);
}

// The pixel's footprint on a surface of normal n (unit) hit at depth t along d (camera z = 1): the
// square root of the pixel's area there, (t / f) / sqrt(|n . d|) for a pinhole camera (t / f on a
// fronto-parallel plane wherever it is in the image, so both cameras of a pair see a point of such
// a plane with the same footprint).
double surface_footprint(const Eigen::Vector3d& n, const Eigen::Vector3d& d, double t, double pixel_angle) {
  return pixel_angle * t / std::sqrt(std::max(0.02, std::fabs(n.dot(d))));
}
double ground_footprint(const Eigen::Vector3d& d, double t, double pixel_angle) {
  return surface_footprint({0, -1, 0}, d, t, pixel_angle);
}
double ground_shade(uint32_t seed, double x, double z, double footprint) {
  return 0.85 * noise(seed, x * 0.5, z * 0.5, footprint * 0.5);
}

// The grey level of primitive `id` hit at o + t d; `pixel_angle` is the angle one pixel subtends.
// `box_axis` is hit_box's entry axis for this ray when id is a box (-2: compute it here).
double shade(const Scene& sc, const Ids& ids, int id, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t,
             double pixel_angle, int box_axis = -2) {
  if (id == 0) return kSkyGrey;
  const Eigen::Vector3d p = o + t * d;
  auto footprint = [&](const Eigen::Vector3d& n) { return surface_footprint(n, d, t, pixel_angle); };
  if (id == 1) return ground_shade(sc.texture_seed, p.x(), p.z(), ground_footprint(d, t, pixel_angle));
  if (id < ids.boxes) {
    const int k = id - ids.cylinders;
    const Cylinder& c = sc.cylinders[std::size_t(k)];
    const Eigen::Vector3d n(p.x() - c.x_m, 0, p.z() - c.z_m);
    const double ang = fast_atan2(p.z() - c.z_m, p.x() - c.x_m);
    return paint(sc, c.surface, sc.texture_seed + 101 + uint32_t(k), ang * c.radius_m, p.y(), footprint(n / c.radius_m),
                 1.0, 0);
  }
  if (id < ids.branches) {
    const int k = id - ids.boxes;
    const Box& b = sc.boxes[std::size_t(k)];
    int axis = box_axis;
    if (axis == -2) hit_box(b, o, d, axis);
    // The face's normal is the unit vector of its axis: n . d is d[axis] exactly.
    const double u = axis == 0 ? p.z() : p.x(), v = axis == 1 ? p.z() : p.y();
    const double foot = pixel_angle * t / std::sqrt(std::max(0.02, std::fabs(d[std::max(axis, 0)])));
    return paint(sc, b.surface, sc.texture_seed + 977 + uint32_t(k), u, v, foot, 0.7, axis == 0 ? 1 : 0);
  }
  const int k = id - ids.branches;
  const Branch& br = sc.branches[std::size_t(k)];
  const Eigen::Vector3d ax = branch_axis(br), w = p - branch_root(br);
  const Eigen::Vector3d radial = w - w.dot(ax) * ax;
  const double ang = fast_atan2(radial.y(), radial.dot(Eigen::Vector3d(ax.z(), 0, -ax.x())));
  return 0.7 *
         noise(sc.texture_seed + 5003 + uint32_t(k), w.dot(ax), ang * br.radius_m, footprint(radial / br.radius_m));
}

// The image-space box a world AABB can cover: the projections of its corners in front of the
// near plane and of its edges' crossings of that plane (the box clipped to the visible half-space).
cv::Rect screen_box(const Rig& rig, int w, int h, const Eigen::Matrix3d& axes, const Eigen::Vector3d& cam,
                    const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Eigen::Vector3d q[8];
  for (int c = 0; c < 8; ++c)
    q[c] = axes.transpose() *
           (Eigen::Vector3d((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z()) - cam);
  double u0 = kInf, u1 = -kInf, v0 = kInf, v1 = -kInf;
  auto add = [&](const Eigen::Vector3d& p) {
    const double u = rig.focal_px * p.x() / p.z() + rig.cx_px, v = rig.focal_px * p.y() / p.z() + rig.cy_px;
    u0 = std::min(u0, u);
    u1 = std::max(u1, u);
    v0 = std::min(v0, v);
    v1 = std::max(v1, v);
  };
  for (int c = 0; c < 8; ++c) {
    if (q[c].z() >= kNearM) add(q[c]);
    for (int bit = 1; bit < 8; bit <<= 1) {  // the edges from corner c to c | bit
      if (c & bit) continue;
      const Eigen::Vector3d& a = q[c];
      const Eigen::Vector3d& e = q[c | bit];
      if ((a.z() < kNearM) != (e.z() < kNearM)) add(a + (e - a) * ((kNearM - a.z()) / (e.z() - a.z())));
    }
  }
  if (!(u1 >= u0)) return {};  // entirely behind the camera
  const int x0 = int(std::clamp(std::floor(u0) - 1, 0.0, double(w)));
  const int x1 = int(std::clamp(std::ceil(u1) + 2, 0.0, double(w)));
  const int y0 = int(std::clamp(std::floor(v0) - 1, 0.0, double(h)));
  const int y1 = int(std::clamp(std::ceil(v1) + 2, 0.0, double(h)));
  return x1 > x0 && y1 > y0 ? cv::Rect(x0, y0, x1 - x0, y1 - y0) : cv::Rect();
}

// A primitive whose screen box covers an image row: its columns [x0_px, x1_px) and id.
struct RowCandidate {
  int x0_px, x1_px, id;
};

// One camera's depth and id buffers, primitive by primitive.
struct Buffers {
  std::vector<double> t;
  std::vector<int> id;
  std::vector<int8_t> box_axis;  // hit_box's entry axis where id is a box
};

class Caster {
 public:
  Caster(const Scene& sc, const Rig& rig, int w, int h, const Eigen::Matrix3d& axes)
      : sc_(sc), ids_(sc), rig_(rig), w_(w), h_(h), axes_(axes) {}

  Eigen::Vector3d direction(double u, double v) const {
    return axes_.col(0) * ((u - rig_.cx_px) / rig_.focal_px) + axes_.col(1) * ((v - rig_.cy_px) / rig_.focal_px) +
           axes_.col(2);
  }

  // The nearest hit of o + t d among all primitives (for rays off the pixel grid: lenses).
  std::pair<double, int> nearest(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = hit_ground(o, d);
    int id = std::isfinite(best) ? 1 : 0;
    auto consider = [&](int pid, double t) {
      if (t < best) {
        best = t;
        id = pid;
      }
    };
    for (std::size_t k = 0; k < sc_.cylinders.size(); ++k)
      consider(ids_.cylinders + int(k), hit_cylinder(sc_.cylinders[k], o, d));
    for (std::size_t k = 0; k < sc_.boxes.size(); ++k) {
      int axis = 0;
      consider(ids_.boxes + int(k), hit_box(sc_.boxes[k], o, d, axis));
    }
    for (std::size_t k = 0; k < sc_.branches.size(); ++k)
      consider(ids_.branches + int(k), hit_branch(sc_.branches[k], o, d));
    return {best, id};
  }

  // The nearest hit of o + t d among `near` (ascending ids, the order nearest() visits them in, so
  // ties resolve alike): the primitives whose screen boxes hold the pixel (column_candidates).
  // `best_axis` receives the entry axis of the winning box.
  std::pair<double, int> nearest_among(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const std::vector<int>& near,
                                       int& best_axis) const {
    double best = hit_ground(o, d);
    int id = std::isfinite(best) ? 1 : 0;
    best_axis = -2;
    for (const int pid : near) {
      int axis = 0;
      const double t = pid < ids_.boxes      ? hit_cylinder(sc_.cylinders[std::size_t(pid - ids_.cylinders)], o, d)
                       : pid < ids_.branches ? hit_box(sc_.boxes[std::size_t(pid - ids_.boxes)], o, d, axis)
                                             : hit_branch(sc_.branches[std::size_t(pid - ids_.branches)], o, d);
      if (t < best) {
        best = t;
        id = pid;
        best_axis = axis;
      }
    }
    return {best, id};
  }

  // The ids among a row's candidates (row_candidates) whose screen boxes hold column u, into `near`.
  static void column_candidates(const std::vector<RowCandidate>& row, int u, std::vector<int>& near) {
    near.clear();
    for (const RowCandidate& c : row)
      if (u >= c.x0_px && u < c.x1_px) near.push_back(c.id);
  }

  // For each image row, the ids (ascending) whose screen boxes cover it, with the boxes' columns.
  std::vector<std::vector<RowCandidate>> row_candidates(const std::vector<cv::Rect>& boxes) const {
    std::vector<std::vector<RowCandidate>> rows(static_cast<std::size_t>(h_));
    for (std::size_t pid = 0; pid < boxes.size(); ++pid) {
      const cv::Rect& r = boxes[pid];
      if (r.width <= 0 || r.height <= 0) continue;
      for (int v = r.y; v < r.y + r.height; ++v) rows[std::size_t(v)].push_back({r.x, r.x + r.width, int(pid)});
    }
    return rows;
  }

  // Screen boxes of every primitive (index = id) for a camera at `cam`.
  std::vector<cv::Rect> boxes(const Eigen::Vector3d& cam) const {
    std::vector<cv::Rect> r(std::size_t(ids_.branches) + sc_.branches.size());
    for (std::size_t k = 0; k < sc_.cylinders.size(); ++k) {
      const Cylinder& c = sc_.cylinders[k];
      r[std::size_t(ids_.cylinders) + k] =
          screen_box(rig_, w_, h_, axes_, cam, {c.x_m - c.radius_m, -c.height_m, c.z_m - c.radius_m},
                     {c.x_m + c.radius_m, 0.0, c.z_m + c.radius_m});
    }
    for (std::size_t k = 0; k < sc_.boxes.size(); ++k) {
      const Box& b = sc_.boxes[k];
      r[std::size_t(ids_.boxes) + k] =
          screen_box(rig_, w_, h_, axes_, cam, {b.x0_m, -b.height_m, b.z0_m}, {b.x1_m, 0.0, b.z1_m});
    }
    for (std::size_t k = 0; k < sc_.branches.size(); ++k) {
      const Branch& br = sc_.branches[k];
      const Eigen::Vector3d a = branch_root(br), e = a + br.length_m * branch_axis(br);
      const Eigen::Vector3d pad = Eigen::Vector3d::Constant(br.radius_m);
      r[std::size_t(ids_.branches) + k] =
          screen_box(rig_, w_, h_, axes_, cam, a.cwiseMin(e) - pad, a.cwiseMax(e) + pad);
    }
    return r;
  }

  // Depth and id of every pixel centre: the ground, then each primitive over its screen box.
  // `b` is overwritten whole (its storage is reused from frame to frame).
  void trace(const Eigen::Vector3d& cam, const std::vector<cv::Rect>& boxes, Buffers& b) const {
    b.t.assign(std::size_t(w_) * std::size_t(h_), kInf);
    b.id.assign(b.t.size(), 0);
    b.box_axis.assign(b.t.size(), int8_t(-2));
    // No roll: a ray's y component, so its ground hit's depth, depends on the row alone.
    for (int v = 0; v < h_; ++v) {
      const double t = hit_ground(cam, direction(rig_.cx_px, v));
      if (!std::isfinite(t)) continue;
      std::fill_n(b.t.begin() + std::ptrdiff_t(v) * w_, w_, t);
      std::fill_n(b.id.begin() + std::ptrdiff_t(v) * w_, w_, 1);
    }
    auto raster = [&](int pid, auto&& hit) {
      const cv::Rect& r = boxes[std::size_t(pid)];
      for (int v = r.y; v < r.y + r.height; ++v)
        for (int u = r.x; u < r.x + r.width; ++u) {
          const std::size_t i = std::size_t(v) * std::size_t(w_) + std::size_t(u);
          int axis = -2;
          const double t = hit(direction(u, v), axis);
          if (t < b.t[i]) {
            b.t[i] = t;
            b.id[i] = pid;
            b.box_axis[i] = int8_t(axis);
          }
        }
    };
    for (std::size_t k = 0; k < sc_.cylinders.size(); ++k)
      raster(ids_.cylinders + int(k),
             [&](const Eigen::Vector3d& d, int&) { return hit_cylinder(sc_.cylinders[k], cam, d); });
    for (std::size_t k = 0; k < sc_.boxes.size(); ++k)
      raster(ids_.boxes + int(k),
             [&](const Eigen::Vector3d& d, int& axis) { return hit_box(sc_.boxes[k], cam, d, axis); });
    for (std::size_t k = 0; k < sc_.branches.size(); ++k) {
      const BranchFromOrigin from(sc_.branches[k], cam);
      raster(ids_.branches + int(k),
             [&](const Eigen::Vector3d& d, int&) { return hit_branch(sc_.branches[k], from, d); });
    }
  }

  // Grey levels: one shading per pixel; with antialias, pixels whose id differs from a
  // 4-neighbour's average four samples at (+-1/4, +-1/4).
  cv::Mat grey(const Eigen::Vector3d& cam, const Buffers& b, const std::vector<cv::Rect>& boxes, bool antialias) const {
    cv::Mat img(h_, w_, CV_8U);
    const double pixel_angle = 1.0 / rig_.focal_px;
    std::vector<double> row_footprint(std::size_t(h_), 0.0);
    for (int v = 0; v < h_; ++v) {
      const Eigen::Vector3d d = direction(rig_.cx_px, v);
      const double t = hit_ground(cam, d);
      if (std::isfinite(t)) row_footprint[std::size_t(v)] = ground_footprint(d, t, pixel_angle);
    }
    const std::vector<std::vector<RowCandidate>> rows = row_candidates(boxes);
    std::vector<int> near;  // an edge pixel's candidates
    for (int v = 0; v < h_; ++v)
      for (int u = 0; u < w_; ++u) {
        const std::size_t i = std::size_t(v) * std::size_t(w_) + std::size_t(u);
        const int id = b.id[i];
        const bool edge = antialias && ((u > 0 && b.id[i - 1] != id) || (u + 1 < w_ && b.id[i + 1] != id) ||
                                        (v > 0 && b.id[i - std::size_t(w_)] != id) ||
                                        (v + 1 < h_ && b.id[i + std::size_t(w_)] != id));
        double g = 0;
        if (!edge && id == 1) {
          // The ground: the row's depth, the footprint of the row's centre (ground_shade).
          const Eigen::Vector3d d = direction(u, v);
          g = ground_shade(sc_.texture_seed, cam.x() + b.t[i] * d.x(), cam.z() + b.t[i] * d.z(),
                           row_footprint[std::size_t(v)]);
        } else if (!edge) {
          g = shade(sc_, ids_, id, cam, direction(u, v), b.t[i], pixel_angle, b.box_axis[i]);
        } else {
          column_candidates(rows[std::size_t(v)], u, near);
          for (int s = 0; s < 4; ++s) {
            const Eigen::Vector3d d = direction(u + ((s & 1) ? 0.25 : -0.25), v + ((s & 2) ? 0.25 : -0.25));
            int axis = -2;
            const auto [t, sid] = nearest_among(cam, d, near, axis);
            g += 0.25 * shade(sc_, ids_, sid, cam, d, t, pixel_angle, axis);
          }
        }
        img.at<uint8_t>(v, u) = round_grey(g);
      }
    return img;
  }

  const Scene& scene() const { return sc_; }
  const Ids& ids() const { return ids_; }

 private:
  const Scene& sc_;
  Ids ids_;
  const Rig& rig_;
  int w_, h_;
  Eigen::Matrix3d axes_;
};

}  // namespace

Eigen::Matrix3d camera_axes(const CameraPose& pose) {
  const double cy = std::cos(pose.yaw_rad), sy = std::sin(pose.yaw_rad);
  const double cp = std::cos(pose.pitch_rad), sp = std::sin(pose.pitch_rad);
  const Eigen::Vector3d right(cy, 0, -sy), ahead(sy, 0, cy), down(0, 1, 0);
  Eigen::Matrix3d m;
  m.col(0) = right;
  m.col(1) = cp * down + sp * ahead;  // looking up (pitch > 0) tilts the image's down forwards
  m.col(2) = cp * ahead - sp * down;
  return m;
}

StereoFrame render(const Scene& sc, const Rig& rig, int w, int h, const CameraPose& pose, bool antialias,
                   GreyImages grey) {
  const Eigen::Matrix3d axes = camera_axes(pose);
  const Caster caster(sc, rig, w, h, axes);
  const Eigen::Vector3d cam_l = pose.position_m, cam_r = pose.position_m + rig.baseline_m * axes.col(0);
  const std::vector<cv::Rect> boxes_l = caster.boxes(cam_l), boxes_r = caster.boxes(cam_r);
  // Per thread, kept between frames: 5.5 MB at 640x360 that need not be paged in again.
  thread_local Buffers bl, br;
  caster.trace(cam_l, boxes_l, bl);
  caster.trace(cam_r, boxes_r, br);
  StereoFrame f;
  f.left = caster.grey(cam_l, bl, boxes_l, antialias);
  if (grey == GreyImages::both) f.right = caster.grey(cam_r, br, boxes_r, antialias);
  f.disparity_px = cv::Mat::zeros(h, w, CV_32F);
  f.valid_mask = cv::Mat::zeros(h, w, CV_8U);
  f.noc_mask = cv::Mat::zeros(h, w, CV_8U);
  const double fb = rig.focal_px * rig.baseline_m;
  // Both cameras' disparities first (t is the depth: the direction's camera z is 1), in a loop
  // that vectorises.
  thread_local std::vector<double> disp_l, disp_r;
  disp_l.resize(bl.t.size());
  disp_r.resize(br.t.size());
  for (std::size_t i = 0; i < bl.t.size(); ++i) disp_l[i] = fb / bl.t[i];
  for (std::size_t i = 0; i < br.t.size(); ++i) disp_r[i] = fb / br.t[i];
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(w) + std::size_t(u);
      if (bl.id[i] == 0) continue;
      const double disp = disp_l[i];
      if (disp >= 255.0) continue;
      f.disparity_px.at<float>(v, u) = float(disp);
      f.valid_mask.at<uint8_t>(v, u) = 255;
      // Visible from the right camera: the right image at u - d sees (about) the same depth.
      const int ur = int(round_half_away(double(u) - disp));
      if (ur < 0 || ur >= w) continue;
      const std::size_t j = std::size_t(v) * std::size_t(w) + std::size_t(ur);
      if (br.id[j] != 0 && std::fabs(disp_r[j] - disp) <= 1.0) f.noc_mask.at<uint8_t>(v, u) = 255;
    }
  return f;
}

StereoFrame render(const Scene& sc, const Rig& rig, int w, int h, const Eigen::Vector3d& cam, double k1) {
  CameraPose pose;
  pose.position_m = cam;
  if (k1 == 0.0) return render(sc, rig, w, h, pose, false);
  // The truth of the rectified pair, then the images through distorting lenses.
  StereoFrame f = render(sc, rig, w, h, pose, false);
  const Eigen::Matrix3d axes = camera_axes(pose);
  const Caster caster(sc, rig, w, h, axes);
  const Eigen::Vector3d right_cam = cam + Eigen::Vector3d(rig.baseline_m, 0, 0);
  const double pixel_angle = 1.0 / rig.focal_px;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const double xd = (u - rig.cx_px) / rig.focal_px, yd = (v - rig.cy_px) / rig.focal_px;
      double x = xd, y = yd;
      for (int it = 0; it < 8; ++it) {  // invert x_d = x (1 + k1 r^2)
        const double s = 1.0 + k1 * (x * x + y * y);
        x = xd / s;
        y = yd / s;
      }
      const Eigen::Vector3d dir(x, y, 1.0);
      for (int side = 0; side < 2; ++side) {
        const Eigen::Vector3d& o = side == 0 ? cam : right_cam;
        const auto [t, id] = caster.nearest(o, dir);
        (side == 0 ? f.left : f.right).at<uint8_t>(v, u) =
            round_grey(shade(sc, caster.ids(), id, o, dir, t, pixel_angle));
      }
    }
  return f;
}

void apply_sensor(StereoFrame& f, const Imaging& im, std::mt19937& rng) {
  // Read noise from a table of 65,536 standard normal samples indexed by the generator's bits:
  // a normal_distribution per pixel would cost as much as rendering the frame.
  static const std::vector<float> gauss = [] {
    std::mt19937 g(12345);
    std::normal_distribution<float> n(0.0f, 1.0f);
    std::vector<float> t(65536);
    for (float& x : t) x = n(g);
    return t;
  }();
  for (cv::Mat* m : {&f.left, &f.right}) {
    const bool right = m == &f.right;
    const double gain = right ? im.right_gain : 1.0, offset = right ? im.right_offset_grey : 0.0;
    if (im.noise_grey <= 0 && gain == 1.0 && offset == 0.0) continue;
    // An image not rendered (empty) is of the left's size: its share of draws is taken and dropped.
    const int n = int(m->empty() ? f.left.total() : m->total());
    const double noise = im.noise_grey;
    if (m->empty()) {
      if (noise > 0) rng.discard((static_cast<unsigned long long>(n) + 1) / 2);
      continue;
    }
    uint8_t* px = m->data;
    if (noise <= 0) {
      for (int i = 0; i < n; ++i) px[i] = round_grey(gain * px[i] + offset);
      continue;
    }
    // One draw per pixel pair, in pixel order: its low half for the even pixel, its high half for
    // the odd one. The draws and table reads first, then a loop that vectorises.
    thread_local std::vector<uint32_t> draws;
    thread_local std::vector<float> normal;
    draws.resize(std::size_t(n + 1) / 2);
    normal.resize(std::size_t(n) + 1);
    for (std::size_t k = 0; k < draws.size(); ++k) {
      const uint32_t b = uint32_t(rng());
      normal[2 * k] = gauss[b & 0xFFFF];
      normal[2 * k + 1] = gauss[b >> 16];
    }
    const float* z = normal.data();
    for (int i = 0; i < n; ++i) px[i] = round_grey(gain * px[i] + offset + noise * double(z[i]));
  }
}

}  // namespace parallax::uav
