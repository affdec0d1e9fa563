// The wall along a ray. See pipe_wall_probe.h.
#include "environment/pipe_wall_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "environment/pipe_geom.h"

namespace chainsim {
namespace {

constexpr double kTolerance = 1e-7;   // m, along the ray
constexpr int kMaxIterations = 60;    // regula falsi / bisection steps (a bisection alone needs ~28)
constexpr int kWindow = 3;            // pieces tried on either side of the hint
constexpr int kAllPieces = 8;         // pipes with at most this many pieces: try them all

}  // namespace

WallProbe::WallProbe(const PipeLayout* layout, const std::vector<dGeomID>& geoms)
    : layout_(layout) {
  for (dGeomID g : geoms)
    if (!(layout_ && dGeomGetClass(g) == pipe_geom_class())) others_.push_back(g);
  if (!others_.empty()) {
    ray_ = dCreateRay(nullptr, 1.0);
    dGeomRaySetFirstContact(ray_, 0);
    dGeomRaySetBackfaceCull(ray_, 0);  // a pipe mesh is seen from inside
    dGeomRaySetClosestHit(ray_, 1);
  }
}

WallProbe::~WallProbe() {
  if (ray_) dGeomDestroy(ray_);
}

double WallProbe::bore_gap(const Eigen::Vector3d& x, int lo, int hi, int* piece,
                           Eigen::Vector3d* out) const {
  double best = kNotOwned;
  for (int k = lo; k <= hi; ++k) {
    Eigen::Vector3d dir;
    const double d = pipe_piece_depth(*layout_, k, x, 0.0, &dir);
    if (d == kNotOwned) continue;
    if (best == kNotOwned || d < best) {
      best = d;
      *piece = k;
      *out = dir;
    }
  }
  return best;
}

double WallProbe::bore_gap_near(const Eigen::Vector3d& x, int hint, int* lo, int* hi, int* piece,
                                Eigen::Vector3d* out) const {
  const int n = static_cast<int>(layout_->pieces.size());
  *lo = 0;
  *hi = n - 1;
  if (n > kAllPieces && hint >= 0) {
    *lo = std::max(0, hint - kWindow);
    *hi = std::min(n - 1, hint + kWindow);
  }
  double g = bore_gap(x, *lo, *hi, piece, out);
  if (g == kNotOwned && (*lo > 0 || *hi < n - 1)) {  // the hint was stale: all pieces
    *lo = 0;
    *hi = n - 1;
    g = bore_gap(x, *lo, *hi, piece, out);
  }
  return g;
}

double WallProbe::pipe_wall_gap(const Eigen::Vector3d& x, int* hint, WallHit* hit) const {
  if (!has_pipe()) return kNotOwned;
  int lo, hi, k = -1;
  Eigen::Vector3d out;
  const double g = bore_gap_near(x, *hint, &lo, &hi, &k, &out);
  if (g == kNotOwned) return g;
  *hint = k;
  hit->t = g;
  hit->normal = -out;
  hit->point = x - g * out;
  hit->pipe = true;
  return g;
}

bool WallProbe::cast_pipe(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_t,
                          int* hint, WallHit* hit) const {
  if (!has_pipe() || !(max_t > 0)) return false;
  int lo, hi, k0 = -1, k1 = -1, k = -1;
  Eigen::Vector3d dir0, dir1, dir;
  const double g0 = bore_gap_near(o, *hint, &lo, &hi, &k0, &dir0);
  if (!(g0 < 0)) return false;  // origin past an open end (free) or in the wall
  double g1 = bore_gap(o + max_t * d, lo, hi, &k1, &dir1);
  // no piece owns the far end: past an open end, or deep in the wall (more
  // than 2 radii from every axis); step back until a piece owns the point
  for (int k = 7; g1 == kNotOwned && k > 0; --k) {
    const double te = max_t * k / 8.0;
    g1 = bore_gap(o + te * d, lo, hi, &k1, &dir1);
    if (g1 >= 0) max_t = te;
  }
  if (!(g1 >= 0)) return false;  // inside (or free) at the end of the reach

  double t = 0;
  const PipePiece& p0 = layout_->pieces[k0];
  if (k0 == k1 && p0.kind == PipePiece::Kind::Straight && p0.holes[0] < 0 && p0.holes[1] < 0) {
    // one straight piece without openings owns both ends: |q_perp + t d_perp| = R
    const Eigen::Vector3d& tan = p0.start.tangent;
    const Eigen::Vector3d q = o - p0.start.point;
    const Eigen::Vector3d qp = q - q.dot(tan) * tan;
    const Eigen::Vector3d dp = d - d.dot(tan) * tan;
    const double a = dp.squaredNorm(), b = qp.dot(dp), c = qp.squaredNorm() - p0.radius_m * p0.radius_m;
    const double disc = b * b - a * c;  // > 0: c < 0 inside
    if (!(a > 0) || !(disc >= 0)) return false;
    t = std::min(max_t, (-b + std::sqrt(disc)) / a);
    k = k0;
    const Eigen::Vector3d x = o + t * d;
    const Eigen::Vector3d r = (x - p0.start.point) - (x - p0.start.point).dot(tan) * tan;
    dir = r.norm() > 0 ? Eigen::Vector3d(r.normalized()) : dir1;
  } else {
    // regula falsi (Illinois) on the bracket [a, b], g(a) < 0 <= g(b); a
    // point no piece owns counts as inside and is bisected past
    double a = 0, b = max_t, ga = g0, gb = g1;
    int side = 0;
    k = k1;
    dir = dir1;
    for (int it = 0; it < kMaxIterations && b - a > kTolerance; ++it) {
      double m = (ga == kNotOwned) ? 0.5 * (a + b) : b - gb * (b - a) / (gb - ga);
      if (!(m > a && m < b)) m = 0.5 * (a + b);
      int km = -1;
      Eigen::Vector3d dm;
      const double gm = bore_gap(o + m * d, lo, hi, &km, &dm);
      if (gm >= 0) {
        b = m;
        gb = gm;
        k = km;
        dir = dm;
        if (side == 1 && ga != kNotOwned) ga *= 0.5;
        side = 1;
      } else {
        a = m;
        ga = gm;
        if (side == -1) gb *= 0.5;
        side = -1;
      }
      if (gm >= 0 && gm < 1e-10) break;
    }
    t = b;
  }
  hit->t = t;
  hit->point = o + t * d;
  hit->normal = -dir;
  hit->pipe = true;
  *hint = k;
  return true;
}

bool WallProbe::cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_t,
                     int* hint, WallHit* hit) const {
  bool found = cast_pipe(o, d, max_t, hint, hit);
  if (!ray_) return found;
  dGeomRaySet(ray_, o.x(), o.y(), o.z(), d.x(), d.y(), d.z());
  dGeomRaySetLength(ray_, found ? hit->t : max_t);
  for (dGeomID g : others_) {
    dContactGeom c;
    if (dCollide(ray_, g, 1, &c, sizeof(dContactGeom)) < 1) continue;
    if (found && c.depth >= hit->t) continue;
    Eigen::Vector3d nrm(c.normal[0], c.normal[1], c.normal[2]);
    if (nrm.dot(d) > 0) nrm = -nrm;  // towards the ray's origin: into the free space
    hit->t = c.depth;
    hit->point = Eigen::Vector3d(c.pos[0], c.pos[1], c.pos[2]);
    hit->normal = nrm.normalized();
    hit->pipe = false;
    found = true;
    dGeomRaySetLength(ray_, c.depth);
  }
  return found;
}

}  // namespace chainsim
