// Pipe network layout and bore queries. See pipe_path.h.
#include "environment/pipe_path.h"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <sstream>

#include "model/units.h"
#include "text/number_text.h"

namespace chainsim {
namespace {

Eigen::Vector3d left_of(const PipeFrame& f) { return f.up.cross(f.tangent); }

// the frame turned by angle about axis (a rigid rotation of tangent and up)
PipeFrame turned(const PipeFrame& f, const Eigen::Vector3d& axis, double angle) {
  const Eigen::AngleAxisd r(angle, axis.normalized());
  PipeFrame out = f;
  out.tangent = (r * f.tangent).normalized();
  out.up = r * f.up;
  out.up = (out.up - out.up.dot(out.tangent) * out.tangent).normalized();
  return out;
}

PipePiece straight(const PipeFrame& at, double length, double radius, int segment) {
  PipePiece p;
  p.kind = PipePiece::Kind::Straight;
  p.radius_m = radius;
  p.segment = segment;
  p.start = at;
  p.length_m = length;
  return p;
}

// an elbow from frame at, bending towards bend_dir (a unit vector across at's tangent)
PipePiece elbow(const PipeFrame& at, const Eigen::Vector3d& bend_dir, const PipeSegment& g, double radius,
                int segment) {
  PipePiece p;
  p.kind = PipePiece::Kind::Elbow;
  p.radius_m = radius;
  p.segment = segment;
  p.start = at;
  p.bend_radius_m = g.bend_radius_m;
  p.angle_rad = g.angle_deg * kRadPerDeg;
  p.centre = at.point + g.bend_radius_m * bend_dir;
  p.u = -bend_dir;
  p.v = at.tangent;
  p.normal = p.u.cross(p.v).normalized();
  return p;
}

}  // namespace

PipeLayout layout_pipe(const PipeSpec& spec) {
  if (!(spec.inner_diameter_m > 0) || !std::isfinite(spec.inner_diameter_m))
    throw PipeLayoutError(-1, "inner_diameter_m must be > 0 (is " + general_text(spec.inner_diameter_m) + ")");
  if (spec.segments.empty()) throw PipeLayoutError(-1, "a pipe needs at least one segment");
  if (!(std::fabs(spec.slope_deg) <= 90))
    throw PipeLayoutError(-1, "slope_deg must be in [-90, 90] (is " + general_text(spec.slope_deg) + ")");
  const double radius = spec.inner_diameter_m / 2;
  PipeLayout out;
  out.radius_m = radius;

  double slope = spec.slope_deg;
  const PipeSegment& first = spec.segments[0];
  if (first.type == PipeSegment::Type::Straight && !std::isnan(first.slope_deg)) {
    if (!(std::fabs(first.slope_deg) <= 90))
      throw PipeLayoutError(0, "slope_deg must be in [-90, 90] (is " + general_text(first.slope_deg) + ")");
    slope = first.slope_deg;
  }
  const double h = spec.heading_deg * kRadPerDeg, s = slope * kRadPerDeg;
  PipeFrame f;
  f.point = spec.entry_m;
  f.tangent = Eigen::Vector3d(std::cos(s) * std::cos(h), std::cos(s) * std::sin(h), std::sin(s));
  f.up = Eigen::Vector3d(-std::sin(s) * std::cos(h), -std::sin(s) * std::sin(h), std::cos(s));
  out.entry = f;
  PipeFrame entry_out = f;
  entry_out.tangent = -f.tangent;
  out.open_ends.push_back(entry_out);
  if (first.type == PipeSegment::Type::Straight) out.entry_straight_m = first.length_m;

  for (size_t k = 0; k < spec.segments.size(); ++k) {
    const PipeSegment& g = spec.segments[k];
    const int seg = static_cast<int>(k);
    if (k > 0 && !std::isnan(g.slope_deg))
      throw PipeLayoutError(seg, "slope_deg is only allowed on the first segment (change the "
                                 "direction with an elbow)");
    const Eigen::Vector3d bend_dir =
        std::cos(g.direction_deg * kRadPerDeg) * f.up + std::sin(g.direction_deg * kRadPerDeg) * left_of(f);
    switch (g.type) {
      case PipeSegment::Type::Straight: {
        if (!(g.length_m > 0) || !std::isfinite(g.length_m))
          throw PipeLayoutError(seg, "length_m must be > 0 (is " + general_text(g.length_m) + ")");
        out.pieces.push_back(straight(f, g.length_m, radius, seg));
        f.point += g.length_m * f.tangent;
        break;
      }
      case PipeSegment::Type::Elbow:
      case PipeSegment::Type::Split: {
        if (!(g.bend_radius_m > radius) || !std::isfinite(g.bend_radius_m))
          throw PipeLayoutError(seg, "bend_radius_m must be larger than the inner radius " +
                                         general_text(radius) + " m (is " + general_text(g.bend_radius_m) + ")");
        if (!(g.angle_deg > 0 && g.angle_deg <= 180))
          throw PipeLayoutError(seg, "angle_deg must be in (0, 180] (is " + general_text(g.angle_deg) + ")");
        const int followed = static_cast<int>(out.pieces.size());
        out.pieces.push_back(elbow(f, bend_dir, g, radius, seg));
        if (g.type == PipeSegment::Type::Split) {
          // the other outlet turns the opposite way from the same start; each
          // opens the other's wall where their bores overlap
          out.pieces.push_back(elbow(f, -bend_dir, g, radius, seg));
          out.pieces[followed].holes[0] = followed + 1;
          out.pieces[followed + 1].holes[0] = followed;
          out.open_ends.push_back(pipe_piece_frame(out.pieces[followed + 1], 1.0));
        }
        f = pipe_piece_frame(out.pieces[followed], 1.0);
        break;
      }
      case PipeSegment::Type::Tee: {
        if (!(g.run_length_m > 2 * radius) || !std::isfinite(g.run_length_m))
          throw PipeLayoutError(seg, "run_length_m must be larger than the inner diameter " +
                                         general_text(2 * radius) + " m (is " + general_text(g.run_length_m) + ")");
        if (!(g.branch_length_m > radius) || !std::isfinite(g.branch_length_m))
          throw PipeLayoutError(seg, "branch_length_m must be larger than the inner radius " +
                                         general_text(radius) + " m (is " + general_text(g.branch_length_m) + ")");
        const int run = static_cast<int>(out.pieces.size());
        out.pieces.push_back(straight(f, g.run_length_m, radius, seg));
        PipeFrame b;
        b.point = f.point + 0.5 * g.run_length_m * f.tangent;
        b = turned(PipeFrame{b.point, f.tangent, f.up}, f.tangent.cross(bend_dir), kPi / 2);
        out.pieces.push_back(straight(b, g.branch_length_m, radius, seg));
        out.pieces[run].holes[0] = run + 1;
        out.pieces[run + 1].holes[0] = run;
        PipeFrame run_end = f;
        run_end.point = f.point + g.run_length_m * f.tangent;
        PipeFrame branch_end = b;
        branch_end.point = b.point + g.branch_length_m * b.tangent;
        out.open_ends.push_back(g.follow_branch ? run_end : branch_end);
        f = g.follow_branch ? branch_end : run_end;
        break;
      }
    }
  }
  out.exit = f;
  out.open_ends.push_back(f);
  return out;
}

PipeFrame pipe_piece_frame(const PipePiece& p, double f) {
  if (p.kind == PipePiece::Kind::Straight) {
    PipeFrame out = p.start;
    out.point = p.start.point + f * p.length_m * p.start.tangent;
    return out;
  }
  const double a = f * p.angle_rad;
  PipeFrame out = turned(p.start, p.normal, a);
  out.point = p.centre + p.bend_radius_m * (std::cos(a) * p.u + std::sin(a) * p.v);
  return out;
}

double elbow_angle(const PipePiece& e, const Eigen::Vector3d& qp) {
  double a = std::atan2(qp.dot(e.v), qp.dot(e.u));
  if (a < -1e-12) a += 2 * kPi;
  return a;
}

// Elbows turn by at most 180 degrees (layout_pipe). With x, y the point along
// u, v, atan2(y, x) is within [0, pi/2] for x > 0 <= y, below -1e-11 for
// -y > 1e-11 x > 0 (so elbow_angle >= 3 pi/2 - rounding), above pi/2 + 1e-10
// for -x > 1e-10 y > 0, and within (0, pi] for y > 0; the margins are far
// above atan2's rounding (1e-16). Elsewhere atan2 decides.
bool elbow_past_end(const PipePiece& e, const Eigen::Vector3d& qp) {
  const double x = qp.dot(e.u), y = qp.dot(e.v), end = e.angle_rad;
  if (x > 0 && y >= 0 && end >= kPi / 2 - 1e-13) return false;
  if (x > 0 && -y > 1e-11 * x && end <= kPi) return true;
  if (x < 0 && -x > 1e-10 * y && y > 0 && end < kPi / 2 + 5e-11) return true;
  if (y > 0 && end >= kPi - 1e-13) return false;
  return elbow_angle(e, qp) > end + 1e-12;
}

double pipe_piece_axis_length(const PipePiece& p) {
  return p.kind == PipePiece::Kind::Straight ? p.length_m : p.bend_radius_m * p.angle_rad;
}

namespace {

// distance vector from piece p's axis to x, or false if x is beyond the piece's ends
bool radial(const PipePiece& p, const Eigen::Vector3d& x, Eigen::Vector3d* d, bool strict) {
  if (p.kind == PipePiece::Kind::Straight) {
    const Eigen::Vector3d q = x - p.start.point;
    const double s = q.dot(p.start.tangent);
    if (strict ? (s <= 0 || s >= p.length_m) : (s < 0 || s > p.length_m)) return false;
    *d = q - s * p.start.tangent;
    return true;
  }
  const Eigen::Vector3d q = x - p.centre;
  const Eigen::Vector3d qp = q - q.dot(p.normal) * p.normal;
  const double rho = qp.norm();
  if (rho < 1e-12) return false;
  if (strict) {
    const double a = elbow_angle(p, qp);
    if (a <= 0 || a >= p.angle_rad) return false;
  } else if (elbow_past_end(p, qp)) {
    return false;
  }
  *d = x - (p.centre + (p.bend_radius_m / rho) * qp);
  return true;
}

}  // namespace

bool pipe_piece_bore_contains(const PipePiece& p, const Eigen::Vector3d& x, double margin_m) {
  Eigen::Vector3d d;
  return radial(p, x, &d, true) && d.norm() < p.radius_m - margin_m;
}

double pipe_piece_depth(const PipeLayout& layout, int k, const Eigen::Vector3d& x, double r,
                        Eigen::Vector3d* dir_out) {
  const PipePiece& p = layout.pieces[k];
  Eigen::Vector3d d;
  if (!radial(p, x, &d, false)) return kNotOwned;
  const double dist = d.norm();
  if (dist > 2 * p.radius_m) return kNotOwned;
  // on the axis: any direction; the depth is negative for any body that fits
  const Eigen::Vector3d dir = dist > 1e-12 ? Eigen::Vector3d(d / dist) : p.start.up;
  for (int h : p.holes) {
    if (h < 0) continue;
    const Eigen::Vector3d wall = x - d + p.radius_m * dir;
    if (pipe_piece_bore_contains(layout.pieces[h], wall, 0.0)) return kNotOwned;
    // a sphere wholly inside the other piece's bore touches no wall (past a
    // split's wedge, the wall point of this piece lies in the wedge): its
    // clearance there
    const PipePiece& o = layout.pieces[h];
    Eigen::Vector3d dh;
    if (!radial(o, x, &dh, true)) continue;
    const double other = dh.norm() + r - o.radius_m;
    if (other < 0) {
      if (dir_out) *dir_out = dh.norm() > 1e-12 ? Eigen::Vector3d(dh / dh.norm()) : o.start.up;
      return other;
    }
    // in both walls (the wedge between a split's outlets): the nearer bore
    // pushes it out, the other piece stays silent
    if (other < dist + r - p.radius_m) return kNotOwned;
  }
  if (dir_out) *dir_out = dir;
  return dist + r - p.radius_m;
}

bool pipe_piece_ball_clear(const PipePiece& p, const Eigen::Vector3d& c, double rho_m) {
  double dist;  // from c to the piece's whole axis line or circle
  if (p.kind == PipePiece::Kind::Straight) {
    const Eigen::Vector3d q = c - p.start.point;
    const double s = q.dot(p.start.tangent);
    if (s + rho_m < 0 || s - rho_m > p.length_m) return true;  // beyond an end
    dist = (q - s * p.start.tangent).norm();
  } else {
    const Eigen::Vector3d q = c - p.centre;
    const double h = q.dot(p.normal);
    const double in_plane = (q - h * p.normal).norm();
    dist = std::hypot(in_plane - p.bend_radius_m, h);
  }
  const double margin = 1e-9;  // m: rounding in the callers' ball radii
  return dist + rho_m + margin < p.radius_m || dist - rho_m - margin > 2 * p.radius_m;
}

double pipe_depth(const PipeLayout& layout, const Eigen::Vector3d& p, double r) {
  double best = kNotOwned;
  for (int k = 0; k < static_cast<int>(layout.pieces.size()); ++k)
    best = std::max(best, pipe_piece_depth(layout, k, p, r, nullptr));
  return best;
}

}  // namespace chainsim
