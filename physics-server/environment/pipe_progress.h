// How far along a pipe network a point is: the arc length of the axis from
// the entry to the point's nearest axis point, following the pipe's pieces
// (a tee's branch counts from the middle of its run). Past the exit (or
// before the entry) the distance along the end's axis is added (subtracted),
// so a chain that leaves the pipe keeps making progress.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "environment/pipe_path.h"

namespace chainsim {

class PipeProgress {
 public:
  explicit PipeProgress(const PipeLayout& layout);
  // metres along the axis from the entry
  double at(const Eigen::Vector3d& p) const;
  // the whole network's axis length up to the exit
  double exit_m() const { return exit_m_; }

 private:
  PipeLayout layout_;
  std::vector<double> offset_m_;   // arc length at each piece's start
  double exit_m_ = 0;
};

}  // namespace chainsim
