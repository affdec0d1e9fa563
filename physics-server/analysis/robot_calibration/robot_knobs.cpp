// The robot-level catalogue (robot_knobs.h).
#include "analysis/robot_calibration/robot_knobs.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace chainsim {

const std::vector<Knob>& robot_knobs() {
  static const std::vector<Knob> k = {
      {"drive_stall", "stall_torque_nm (dc_motor) or fmax_n (screw_drive)", "helicoidal",
       "the helicoidal drive's stall torque or thrust (force-speed line)", 0.5, 2.0},
      {"drive_free_speed", "free_speed_rad_s (dc_motor) or v_free_m_s (screw_drive)", "helicoidal",
       "the helicoidal drive's no-load speed", 0.7, 1.4},
      {"wheel_preload", "preload_n (every wheel set)", "helicoidal",
       "the wheels' spring force on the wall (their grip and centring)", 0.25, 4.0},
      {"wheel_friction", "mu (every wheel set)", "helicoidal",
       "the tyres' friction across the wheel (how much thrust each wheel grips)", 0.3, 2.0},
      {"arm_grip_torque", "kt (all support arm servos)", "support",
       "the support arms' servo torque constant: how hard the arms press the wall (slip of the grip)", 0.1, 1.5},
      {"pad_friction", "mu (every pad)", "support", "the support arms' pads' friction on the wall", 0.2, 2.0},
      {"extension_force", "fmax_n (every linear servo)", "extension",
       "the extension's stall force (force-speed line): how its stroke slows under the load it moves", 0.1, 1.5},
      {"wall_friction", "environment.material.mu", "", "module-pipe Coulomb friction", 0.2, 5.0},
  };
  return k;
}

int robot_knob(const std::string& name) {
  for (size_t k = 0; k < robot_knobs().size(); ++k)
    if (name == robot_knobs()[k].name) return static_cast<int>(k);
  throw std::invalid_argument("no robot knob '" + name + "'");
}

std::string setting_key(const KnobSetting& st) {
  std::ostringstream s;
  for (const auto& [k, v] : st) s << k << "=" << std::llround(v * 1e6) << ";";
  return s.str();
}

double factor_of(const KnobSetting& st, int knob) {
  const auto it = st.find(knob);
  return it == st.end() ? 1.0 : it->second;
}

}  // namespace chainsim
