// The robot-level catalogue: scene and module parameters a robot calibration
// may change (screw drive thrust and free speed, the support arms' grip
// torque, module-pipe friction), each searched as a factor of its nominal
// value on a log scale. docs/calibration.md, "Robot-level calibration".
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

// a robot calibration's error in its input (table, scenes) or a run
struct RobotError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Knob {
  const char* name;     // report name
  const char* param;    // what it sets
  const char* module;   // module type it needs in the chain ("" = any scene)
  const char* meaning;
  double lo, hi;        // range of the factor
};

// indices into this list are the knobs' ids
const std::vector<Knob>& robot_knobs();
// the id of a knob by name
int robot_knob(const std::string& name);

// a setting: knob id -> factor of its nominal value (absent = 1)
using KnobSetting = std::map<int, double>;

// a setting as text, factors rounded to 1e-6: the key of the run cache
std::string setting_key(const KnobSetting& st);
// the factor of a knob in a setting (1 when absent)
double factor_of(const KnobSetting& st, int knob);

}  // namespace chainsim
