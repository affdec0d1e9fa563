#include "environment/pipe_progress.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace chainsim {

namespace {

// arc-length parameter of p on a piece's axis, not clamped to its ends
double axis_param(const PipePiece& piece, const Eigen::Vector3d& p) {
  if (piece.kind == PipePiece::Kind::Straight) return (p - piece.start.point).dot(piece.start.tangent);
  const Eigen::Vector3d d = p - piece.centre;
  double a = std::atan2(d.dot(piece.v), d.dot(piece.u));
  // angles just before the start read as negative, the rest of the circle past the end
  if (a < -0.5 * (2 * M_PI - piece.angle_rad)) a += 2 * M_PI;
  return a * piece.bend_radius_m;
}

Eigen::Vector3d axis_point(const PipePiece& piece, double s) {
  const double len = pipe_piece_axis_length(piece);
  return pipe_piece_frame(piece, len > 0 ? std::clamp(s, 0.0, len) / len : 0.0).point;
}

}  // namespace

PipeProgress::PipeProgress(const PipeLayout& layout) : layout_(layout) {
  offset_m_.assign(layout_.pieces.size(), 0.0);
  for (size_t k = 1; k < layout_.pieces.size(); ++k) {
    // a piece starts on the axis of an earlier one: at its end, or (a tee's
    // branch) in the middle of its run
    const Eigen::Vector3d s = layout_.pieces[k].start.point;
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < k; ++j) {
      const double u = axis_param(layout_.pieces[j], s);
      const double len = pipe_piece_axis_length(layout_.pieces[j]);
      const double d = (axis_point(layout_.pieces[j], u) - s).norm();
      if (d < best - 1e-12) {
        best = d;
        offset_m_[k] = offset_m_[j] + std::clamp(u, 0.0, len);
      }
    }
  }
  exit_m_ = 0;
  for (size_t k = 0; k < layout_.pieces.size(); ++k) {
    const PipePiece& pc = layout_.pieces[k];
    const double len = pipe_piece_axis_length(pc);
    if ((pipe_piece_frame(pc, 1.0).point - layout_.exit.point).norm() < 1e-9) exit_m_ = offset_m_[k] + len;
  }
}

double PipeProgress::at(const Eigen::Vector3d& p) const {
  double best_d = std::numeric_limits<double>::infinity(), best_s = 0;
  for (size_t k = 0; k < layout_.pieces.size(); ++k) {
    const PipePiece& pc = layout_.pieces[k];
    const double len = pipe_piece_axis_length(pc);
    const double u = axis_param(pc, p);
    const double d = (axis_point(pc, u) - p).norm();
    if (d >= best_d - 1e-12) continue;
    best_d = d;
    double s = std::clamp(u, 0.0, len);
    const bool at_entry = k == 0 && (pc.start.point - layout_.entry.point).norm() < 1e-9;
    const bool at_exit = std::abs(offset_m_[k] + len - exit_m_) < 1e-9 &&
                         (pipe_piece_frame(pc, 1.0).point - layout_.exit.point).norm() < 1e-9;
    if (at_entry && u < 0) s = u;
    if (at_exit && u > len) s = u;
    best_s = offset_m_[k] + s;
  }
  return best_s;
}

}  // namespace chainsim
