// Wheel sets. See wheel_def.h.
#include "model/wheel_def.h"

#include <cmath>
#include <stdexcept>

namespace chainsim {

void validate_wheel_set(const WheelSetDef& w, int n_bodies) {
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("wheel set '" + w.name + "': " + what);
  };
  if (w.name.empty()) bad("no name");
  if (w.body < 0 || w.body >= n_bodies) bad("bad body index");
  if (w.count < 1 || w.count > 16) bad("count must be 1..16");
  for (double v : {w.first_deg, w.x_m, w.helix_deg, w.reach_min_m, w.reach_max_m, w.preload_n,
                   w.stiffness_n_m, w.damping_n_s_m, w.mu, w.cornering_per_rad})
    if (!std::isfinite(v)) bad("a value is not finite");
  if (!(w.helix_deg >= 0 && w.helix_deg <= 90)) bad("helix_deg must be in [0, 90]");
  if (!(w.reach_min_m > 0 && w.reach_min_m < w.reach_max_m))
    bad("reach must be [min, max] with 0 < min < max");
  if (!(w.preload_n >= 0)) bad("preload_n must be >= 0");
  if (!(w.stiffness_n_m > 0)) bad("stiffness_n_m must be > 0");
  if (!(w.damping_n_s_m >= 0)) bad("damping_n_s_m must be >= 0");
  if (!(w.mu >= 0)) bad("mu must be >= 0");
  if (!(w.cornering_per_rad >= 0)) bad("cornering_per_rad must be >= 0");
}

void validate_pad(const PadDef& p, int n_bodies) {
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("pad '" + p.name + "': " + what);
  };
  if (p.name.empty()) bad("no name");
  if (p.body < 0 || p.body >= n_bodies) bad("bad body index");
  if (!p.position_m.allFinite() || !p.direction.allFinite() || !(p.direction.norm() > 1e-9))
    bad("bad position or direction");
  if (!(p.reach_m > 0) || !std::isfinite(p.reach_m)) bad("reach_m must be > 0");
  if (!(p.stiffness_n_m > 0) || !std::isfinite(p.stiffness_n_m)) bad("stiffness_n_m must be > 0");
  if (!(p.damping_n_s_m >= 0) || !std::isfinite(p.damping_n_s_m)) bad("damping_n_s_m must be >= 0");
  if (!(p.mu >= 0) || !std::isfinite(p.mu)) bad("mu must be >= 0");
}

}  // namespace chainsim
