// Divergence of the physics. See divergence.h.
#include "physics/divergence.h"

#include <cmath>
#include <cstdio>

#include "physics/world.h"
#include "text/number_text.h"

namespace chainsim {

namespace {

template <typename V>
bool finite(const V& v) {
  return v.allFinite();
}

// "module 3 (rotation) body 'shell': "
std::string body_text(const World& w, int module, int body) {
  return "module " + std::to_string(module) + " (" + w.module_type(module) + ") body '" + w.body_name(module, body) +
         "': ";
}

}  // namespace

bool falling_straight_down(const Eigen::Vector3d& velocity) {
  const double v = velocity.norm();
  return v > 0 && -velocity.z() >= 0.98480775301220806 * v;   // cos 10 deg
}

std::optional<Divergence> find_divergence(const World& w, const DivergenceBounds& bounds) {
  for (int m = 0; m < w.module_count(); ++m) {
    for (int b = 0; b < w.body_count(m); ++b) {
      const World::BodyState s = w.body_state(m, b);
      Divergence d;
      d.module = m;
      d.body = b;
      const std::string who = body_text(w, m, b);
      if (!finite(s.position) || !finite(s.quaternion_wxyz) || !finite(s.linear_velocity) ||
          !finite(s.angular_velocity)) {
        d.non_finite = true;
        d.what = who + "position, orientation or velocity is not a finite number";
        return d;
      }
      const double v = s.linear_velocity.norm();
      const double wv = s.angular_velocity.norm();
      const double x = s.position.cwiseAbs().maxCoeff();
      if (v > bounds.max_speed_m_s)
        d.what = who + "speed " + fixed_text(v, 1) + " m/s over the bound of " + fixed_text(bounds.max_speed_m_s, 0) +
                 " m/s" +
                 (falling_straight_down(s.linear_velocity) ? ", falling straight down (has it left the environment?)"
                                                            : "");
      else if (wv > bounds.max_angular_speed_rad_s)
        d.what = who + "angular speed " + fixed_text(wv, 0) + " rad/s over the bound of " +
                 fixed_text(bounds.max_angular_speed_rad_s, 0) + " rad/s";
      else if (x > bounds.max_coordinate_m)
        d.what = who + "position " + fixed_text(x, 0) + " m from the origin, over the bound of " +
                 fixed_text(bounds.max_coordinate_m, 0) + " m";
      if (!d.what.empty()) return d;
    }
  }
  // checked after the bodies: a blown-up body is named for its speed first
  const World::Penetration p = w.deepest_contact();
  if (p.module >= 0 && p.depth_m > bounds.max_penetration_m) {
    Divergence d;
    d.module = p.module;
    d.body = p.body;
    d.what = body_text(w, p.module, p.body) + fixed_text(p.depth_m * 1e3, 1) +
             " mm inside the environment or another module, over the bound of " +
             fixed_text(bounds.max_penetration_m * 1e3, 0) + " mm";
    return d;
  }
  return std::nullopt;
}

}  // namespace chainsim
