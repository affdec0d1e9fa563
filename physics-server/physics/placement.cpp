// Chain placement. See placement.h.
#include "physics/placement.h"

#include <sstream>
#include <stdexcept>

#include "environment/pipe_path.h"

namespace chainsim {

void place_chain_at_pipe_entry(WorldConfig* cfg, ChainModel* chain, double inset_m) {
  if (cfg->environment.type != EnvironmentType::Pipe)
    throw std::invalid_argument("placement at the pipe entry needs environment type 'pipe'");
  const PipeLayout layout = layout_pipe(cfg->environment.pipe);
  const double length = chain->length_m;
  if (inset_m < 0 || inset_m + length > layout.entry_straight_m) {
    std::ostringstream s;
    s << "the chain (" << length << " m) plus the inset (" << inset_m
      << " m) does not fit in the pipe's first straight segment (" << layout.entry_straight_m
      << " m; it must start with a straight segment at least that long)";
    throw std::invalid_argument(s.str());
  }
  const PipeFrame& e = layout.entry;
  Eigen::Matrix3d r;
  r.col(0) = e.tangent;
  r.col(1) = e.up.cross(e.tangent);
  r.col(2) = e.up;
  cfg->head_orientation = Eigen::Quaterniond(r);
  cfg->head_position = e.point + (inset_m + length) * e.tangent;
  lay_chain(chain, *cfg);
}

}  // namespace chainsim
