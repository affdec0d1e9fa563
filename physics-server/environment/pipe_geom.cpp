// Analytic pipe colliders. See pipe_geom.h for what is exact and what is sampled.
#include "environment/pipe_geom.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include "model/units.h"

namespace chainsim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kSegmentSamples = 9;   // along a capsule axis, box edge or cylinder side (elbows)
constexpr int kRimSamples = 12;      // around a cylinder rim
constexpr int kRefineIterations = 14;  // golden-section steps: interval x 0.618^14 ~ 1e-3

struct PipeGeomData {
  const PipeLayout* layout;
  int piece;
  dReal aabb[6];
};

using Vec = Eigen::Vector3d;

Vec to_vec(const dReal* p) { return Vec(p[0], p[1], p[2]); }
// column c of an ODE rotation matrix (3 rows of 4)
Vec column(const dReal* r, int c) { return Vec(r[c], r[4 + c], r[8 + c]); }

// the deepest candidate contacts of one collision, fixed capacity
class Candidates {
 public:
  void add(const Vec& body_point, const Vec& dir_out, double depth) {
    if (!(depth > 0)) return;
    int slot = n_;
    if (n_ == kCap) {  // full: replace the shallowest if this one is deeper
      slot = 0;
      for (int i = 1; i < n_; ++i)
        if (c_[i].depth < c_[slot].depth) slot = i;
      if (c_[slot].depth >= depth) return;
    } else {
      ++n_;
    }
    c_[slot] = {body_point, dir_out, depth};
  }
  // writes the deepest min(n, max) contacts, deepest first
  int emit(dGeomID pipe, dGeomID other, int flags, dContactGeom* contact, int skip) {
    std::sort(c_, c_ + n_, [](const C& a, const C& b) { return a.depth > b.depth; });
    const int n = std::min(n_, std::max(1, flags & 0xffff));
    for (int i = 0; i < n; ++i) {
      dContactGeom* g = reinterpret_cast<dContactGeom*>(reinterpret_cast<char*>(contact) + i * skip);
      for (int j = 0; j < 3; ++j) {
        g->pos[j] = c_[i].point[j];
        g->normal[j] = c_[i].dir[j];  // o1 = the pipe: moving it outwards separates
      }
      g->pos[3] = g->normal[3] = 0;
      g->depth = c_[i].depth;
      g->g1 = pipe;
      g->g2 = other;
      g->side1 = g->side2 = -1;
    }
    return n;
  }

 private:
  struct C {
    Vec point, dir;
    double depth;
  };
  static constexpr int kCap = 48;
  C c_[kCap];
  int n_ = 0;
};

// cos and sin of the rim's sample angles i 2 pi / kRimSamples
struct RimTable {
  double cos[kRimSamples], sin[kRimSamples];
  RimTable() {
    const double step = 2 * kPi / kRimSamples;
    for (int i = 0; i < kRimSamples; ++i) {
      const volatile double t = i * step;  // at run time, as before (no constant folding)
      cos[i] = std::cos(t);
      sin[i] = std::sin(t);
    }
  }
};

// the table, computed once (the same values as computing them each time:
// std::cos of the same argument)
const RimTable& rim_table() {
  static const RimTable table;
  return table;
}

struct Query {
  const PipeLayout& layout;
  int k;
  const PipePiece& piece;
  Candidates* out;

  double depth(const Vec& x, double r, Vec* dir) const {
    return pipe_piece_depth(layout, k, x, r, dir);
  }
  // adds the contact of a sphere (x, r) if it penetrates
  void point(const Vec& x, double r) const {
    Vec dir;
    const double d = depth(x, r, &dir);
    if (d > 0) out->add(x + r * dir, dir, d);
  }
  bool exact_lines() const {
    return piece.kind == PipePiece::Kind::Straight && piece.holes[0] < 0 && piece.holes[1] < 0;
  }
  // the parameter range [u0, u1] of a + u (b - a), 0 <= u <= 1, inside the
  // piece's ends (two half-spaces through its end cross-sections)
  bool clip(const Vec& a, const Vec& b, double* u0, double* u1) const {
    Vec n0, c0, n1, c1;
    if (piece.kind == PipePiece::Kind::Straight) {
      c0 = piece.start.point;
      n0 = piece.start.tangent;
      c1 = piece.start.point + piece.length_m * piece.start.tangent;
      n1 = -piece.start.tangent;
    } else {
      c0 = c1 = piece.centre;
      n0 = piece.v;
      n1 = std::sin(piece.angle_rad) * piece.u - std::cos(piece.angle_rad) * piece.v;
    }
    double lo = 0, hi = 1;
    for (int h = 0; h < 2; ++h) {
      const Vec& n = h ? n1 : n0;
      const Vec& c = h ? c1 : c0;
      const double ga = (a - c).dot(n), gb = (b - c).dot(n);
      if (ga < 0 && gb < 0) return false;
      if (ga < 0) lo = std::max(lo, ga / (ga - gb));
      if (gb < 0) hi = std::min(hi, ga / (ga - gb));
    }
    *u0 = lo;
    *u1 = hi;
    return lo <= hi;
  }
  double depth_on(const Vec& a, const Vec& b, double u, double r) const {
    Vec dir;
    const double d = depth(a + u * (b - a), r, &dir);
    return std::isfinite(d) ? d : -1e9;
  }
  // golden-section search for the deepest point of a + u (b - a) in [lo, hi]
  double refine(const Vec& a, const Vec& b, double lo, double hi, double r) const {
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = depth_on(a, b, x1, r), f2 = depth_on(a, b, x2, r);
    for (int i = 0; i < kRefineIterations; ++i) {
      if (f1 < f2) {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + g * (hi - lo);
        f2 = depth_on(a, b, x2, r);
      } else {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - g * (hi - lo);
        f1 = depth_on(a, b, x1, r);
      }
    }
    return 0.5 * (lo + hi);
  }
  // a line segment of spheres of radius r (a capsule's axis, a box edge):
  // its deepest points inside the piece; ends: also a + 0 and a + 1 (b)
  void segment(const Vec& a, const Vec& b, double r, bool ends) const {
    double u0, u1;
    if (!clip(a, b, &u0, &u1)) return;
    if (ends || u0 > 0) point(a + u0 * (b - a), r);
    if (u1 - u0 < 1e-9) return;
    if (ends || u1 < 1) point(a + u1 * (b - a), r);
    if (exact_lines()) return;
    double d[kSegmentSamples];
    const double step = (u1 - u0) / (kSegmentSamples - 1);
    for (int i = 0; i < kSegmentSamples; ++i) d[i] = depth_on(a, b, u0 + i * step, r);
    for (int i = 1; i + 1 < kSegmentSamples; ++i) {
      if (d[i] > d[i - 1] && d[i] >= d[i + 1] && d[i] > -1e8) {
        const double u = refine(a, b, u0 + (i - 1) * step, u0 + (i + 1) * step, r);
        point(a + u * (b - a), r);
      }
    }
  }
  // a circle (centre c, in the plane of orthonormal e1, e2, radius rc): its locally deepest points
  void rim(const Vec& c, const Vec& e1, const Vec& e2, double rc) const {
    double d[kRimSamples];
    const double step = 2 * kPi / kRimSamples;
    auto at_cs = [&](double cs, double sn) { return Vec(c + rc * (cs * e1 + sn * e2)); };
    auto at = [&](double t) { return at_cs(std::cos(t), std::sin(t)); };
    auto f_at = [&](const Vec& x) {
      Vec dir;
      const double v = depth(x, 0.0, &dir);
      return std::isfinite(v) ? v : -1e9;
    };
    auto f = [&](double t) { return f_at(at(t)); };
    const RimTable& table = rim_table();
    for (int i = 0; i < kRimSamples; ++i) d[i] = f_at(at_cs(table.cos[i], table.sin[i]));
    int found = 0, best = 0;
    for (int i = 0; i < kRimSamples; ++i) {
      const double prev = d[(i + kRimSamples - 1) % kRimSamples], next = d[(i + 1) % kRimSamples];
      if (d[i] > d[best]) best = i;
      if (!(d[i] > prev && d[i] >= next) || d[i] < -1e8) continue;
      ++found;
      // golden-section on [t - step, t + step]
      const double g = 0.5 * (std::sqrt(5.0) - 1);
      double lo = (i - 1) * step, hi = (i + 1) * step;
      double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      double f1 = f(x1), f2 = f(x2);
      for (int it = 0; it < kRefineIterations; ++it) {
        if (f1 < f2) {
          lo = x1; x1 = x2; f1 = f2; x2 = lo + g * (hi - lo); f2 = f(x2);
        } else {
          hi = x2; x2 = x1; f2 = f1; x1 = hi - g * (hi - lo); f1 = f(x1);
        }
      }
      point(at(0.5 * (lo + hi)), 0.0);
    }
    if (!found && d[best] > 0) point(at_cs(table.cos[best], table.sin[best]), 0.0);  // flat: a coaxial rim
  }
};

// a ball around the other geom that cannot reach the wall: no contact (exact)
bool clear(dGeomID pipe, const Vec& c, double rho) {
  const auto* gd = static_cast<const PipeGeomData*>(dGeomGetClassData(pipe));
  return pipe_piece_ball_clear(gd->layout->pieces[gd->piece], c, rho);
}

int collide_sphere(dGeomID o1, dGeomID o2, int flags, dContactGeom* contact, int skip) {
  if (clear(o1, to_vec(dGeomGetPosition(o2)), dGeomSphereGetRadius(o2))) return 0;
  const auto* gd = static_cast<const PipeGeomData*>(dGeomGetClassData(o1));
  Candidates cand;
  const Query q{*gd->layout, gd->piece, gd->layout->pieces[gd->piece], &cand};
  q.point(to_vec(dGeomGetPosition(o2)), dGeomSphereGetRadius(o2));
  return cand.emit(o1, o2, flags, contact, skip);
}

int collide_capsule(dGeomID o1, dGeomID o2, int flags, dContactGeom* contact, int skip) {
  const auto* gd = static_cast<const PipeGeomData*>(dGeomGetClassData(o1));
  Candidates cand;
  const Query q{*gd->layout, gd->piece, gd->layout->pieces[gd->piece], &cand};
  dReal radius, length;
  dGeomCapsuleGetParams(o2, &radius, &length);
  const Vec c = to_vec(dGeomGetPosition(o2));
  if (clear(o1, c, 0.5 * length + radius)) return 0;
  const Vec z = column(dGeomGetRotation(o2), 2);
  q.segment(c - 0.5 * length * z, c + 0.5 * length * z, radius, true);
  return cand.emit(o1, o2, flags, contact, skip);
}

int collide_cylinder(dGeomID o1, dGeomID o2, int flags, dContactGeom* contact, int skip) {
  const auto* gd = static_cast<const PipeGeomData*>(dGeomGetClassData(o1));
  Candidates cand;
  const Query q{*gd->layout, gd->piece, gd->layout->pieces[gd->piece], &cand};
  dReal radius, length;
  dGeomCylinderGetParams(o2, &radius, &length);
  const dReal* r = dGeomGetRotation(o2);
  const Vec c = to_vec(dGeomGetPosition(o2));
  if (clear(o1, c, std::hypot(0.5 * length, radius))) return 0;
  const Vec x = column(r, 0), y = column(r, 1), z = column(r, 2);
  q.rim(c - 0.5 * length * z, x, y, radius);
  q.rim(c + 0.5 * length * z, x, y, radius);
  // end faces where the piece has openings: the edge of an opening (the
  // ridge and the wedge between a split's outlets) can reach a face's
  // interior, which a wall without openings never does
  if (q.piece.holes[0] >= 0 || q.piece.holes[1] >= 0) {
    const RimTable& table = rim_table();
    for (const double h : {-0.5 * length, 0.5 * length}) {
      q.point(c + h * z, 0.0);
      for (int i = 0; i < kRimSamples; i += 2)
        for (const double f : {1.0 / 3, 2.0 / 3})
          q.point(c + h * z + f * radius * (table.cos[i] * x + table.sin[i] * y), 0.0);
    }
  }
  // side lines: where a piece's end cuts the cylinder (its lip; clip points
  // only, the rims cover the rest of a straight piece), and in an elbow
  // where the inner side of the bend touches
  auto side = [&](Vec w) {
    w -= w.dot(z) * z;
    if (w.norm() < 1e-9) return;
    w.normalize();
    q.segment(c - 0.5 * length * z + radius * w, c + 0.5 * length * z + radius * w, 0.0, false);
  };
  const PipePiece& p = q.piece;
  if (p.kind == PipePiece::Kind::Straight) {
    const Vec d = c - p.start.point;
    side(d - d.dot(p.start.tangent) * p.start.tangent);  // outwards from the axis
  } else {
    Vec in_plane = c - p.centre;
    in_plane -= in_plane.dot(p.normal) * p.normal;
    if (in_plane.norm() > 1e-9) {
      const Vec tube = p.centre + p.bend_radius_m * in_plane.normalized();
      side(c - tube);        // outwards from the tube's axis
      side(-in_plane);       // towards the bend's centre
    }
  }
  return cand.emit(o1, o2, flags, contact, skip);
}

int collide_box(dGeomID o1, dGeomID o2, int flags, dContactGeom* contact, int skip) {
  const auto* gd = static_cast<const PipeGeomData*>(dGeomGetClassData(o1));
  Candidates cand;
  const Query q{*gd->layout, gd->piece, gd->layout->pieces[gd->piece], &cand};
  dVector3 side;
  dGeomBoxGetLengths(o2, side);
  const dReal* r = dGeomGetRotation(o2);
  const Vec c = to_vec(dGeomGetPosition(o2));
  if (clear(o1, c, 0.5 * std::sqrt(side[0] * side[0] + side[1] * side[1] + side[2] * side[2]))) return 0;
  const Vec h[3] = {0.5 * side[0] * column(r, 0), 0.5 * side[1] * column(r, 1),
                    0.5 * side[2] * column(r, 2)};
  Vec corner[8];
  for (int i = 0; i < 8; ++i)
    corner[i] = c + (i & 1 ? 1 : -1) * h[0] + (i & 2 ? 1 : -1) * h[1] + (i & 4 ? 1 : -1) * h[2];
  for (const Vec& p : corner) q.point(p, 0.0);
  // the 12 edges: corners differing in one bit; their interiors matter where
  // the piece ends cut them, or everywhere in an elbow or a tee
  for (int i = 0; i < 8; ++i)
    for (int bit = 1; bit < 8; bit <<= 1)
      if (!(i & bit)) q.segment(corner[i], corner[i | bit], 0.0, false);
  return cand.emit(o1, o2, flags, contact, skip);
}

dColliderFn* get_collider(int num) {
  switch (num) {
    case dSphereClass: return &collide_sphere;
    case dCapsuleClass: return &collide_capsule;
    case dCylinderClass: return &collide_cylinder;
    case dBoxClass: return &collide_box;
    default: return nullptr;
  }
}

void get_aabb(dGeomID g, dReal aabb[6]) {
  const auto* gd = static_cast<const PipeGeomData*>(dGeomGetClassData(g));
  std::copy(gd->aabb, gd->aabb + 6, aabb);
}

// bounds of a piece's bore (the axis +- the inner radius, and a margin)
void piece_aabb(const PipePiece& p, dReal aabb[6]) {
  Vec lo = Vec::Constant(kInf), hi = Vec::Constant(-kInf);
  const int n = p.kind == PipePiece::Kind::Straight ? 1 : 64;
  for (int i = 0; i <= n; ++i) {
    const Vec x = pipe_piece_frame(p, static_cast<double>(i) / n).point;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  // 2 radii: the region the piece owns (pipe_piece_depth)
  const double m = 2 * p.radius_m + (p.kind == PipePiece::Kind::Elbow ? p.bend_radius_m * 0.01 : 0);
  for (int i = 0; i < 3; ++i) {
    aabb[2 * i] = lo[i] - m;
    aabb[2 * i + 1] = hi[i] + m;
  }
}

int g_class = -1;

dGeomID create(int cls, dSpaceID space, const PipeLayout* layout, int piece) {
  dGeomID g = dCreateGeom(cls);
  auto* gd = static_cast<PipeGeomData*>(dGeomGetClassData(g));
  gd->layout = layout;
  gd->piece = piece;
  piece_aabb(layout->pieces[piece], gd->aabb);
  if (space) dSpaceAdd(space, g);
  return g;
}

}  // namespace

int pipe_geom_class() {
  static std::once_flag once;
  std::call_once(once, [] {
    dGeomClass c{};
    c.bytes = sizeof(PipeGeomData);
    c.collider = &get_collider;
    c.aabb = &get_aabb;
    c.aabb_test = nullptr;
    c.dtor = nullptr;
    g_class = dCreateGeomClass(&c);
    // ODE fills its collider table lazily on the first dCollide of each pair
    // of classes; do it here, once, so that Worlds in several threads never race on it
    PipeLayout layout;
    PipePiece piece;
    piece.radius_m = 1;
    piece.length_m = 1;
    layout.radius_m = 1;
    layout.pieces.push_back(piece);
    dGeomID pipe = create(g_class, nullptr, &layout, 0);
    dGeomID others[4] = {dCreateSphere(nullptr, 0.1), dCreateCapsule(nullptr, 0.1, 0.1),
                         dCreateCylinder(nullptr, 0.1, 0.1), dCreateBox(nullptr, 0.1, 0.1, 0.1)};
    dGeomID plane = dCreatePlane(nullptr, 0, 0, 1, 0);
    dContactGeom cg[8];
    for (dGeomID o : others) {
      dCollide(pipe, o, 8, cg, sizeof(dContactGeom));
      dGeomDestroy(o);
    }
    dCollide(pipe, plane, 8, cg, sizeof(dContactGeom));
    dGeomDestroy(plane);
    dGeomDestroy(pipe);
  });
  return g_class;
}

dGeomID pipe_geom_create(dSpaceID space, const PipeLayout* layout, int piece) {
  return create(pipe_geom_class(), space, layout, piece);
}

}  // namespace chainsim
