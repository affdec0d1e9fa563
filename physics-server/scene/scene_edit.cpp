// Edits of a loaded Scene. See scene_edit.h.
#include "scene/scene_edit.h"

#include <climits>
#include <filesystem>

#include "model/units.h"
#include "physics/placement.h"

namespace chainsim {

namespace {

int32_t param_value(const std::string& who, const std::string& name, int64_t value) {
  if (!is_param_name(name))
    throw SceneError(who + ": parameter name '" + name + "' must be 1 to 15 letters, digits or '_'");
  if (value < INT32_MIN || value > INT32_MAX)
    throw SceneError(who + ": parameter '" + name + "' = " + std::to_string(value) +
                     " is outside the 32-bit range of a program parameter");
  return static_cast<int32_t>(value);
}

void set_param(SceneModule* m, const std::string& name, int32_t value, const std::string& at) {
  m->params[name] = value;
  m->param_at[name] = at;
}

// where an edit sets something, for later messages (check_scene_params)
std::string edited_at(const Scene& s) { return s.source + " (edited)"; }

}  // namespace

bool is_param_name(const std::string& s) {
  if (s.empty() || s.size() > 15) return false;
  for (char ch : s)
    if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_')) return false;
  return true;
}

SceneModule scene_module_of_type(const Scene& s, const std::string& type) {
  const auto get = [&](const std::string& key) {
    const auto it = s.programs.find(key);
    return it == s.programs.end() ? SceneProgram{} : it->second;
  };
  const SceneProgram all = get("all");
  const SceneProgram own = get(type);
  SceneModule m;
  m.type = type;
  const SceneProgram& fw = !own.firmware.empty() ? own : all;
  m.firmware = !fw.firmware.empty() ? fw.firmware : default_firmware(type);
  m.firmware_at = fw.firmware_at;
  m.params = all.params;
  m.param_at = all.param_at;
  for (const auto& [k, v] : own.params) m.params[k] = v;
  for (const auto& [k, v] : own.param_at) m.param_at[k] = v;
  m.may_stay_silent = own.may_stay_silent.value_or(all.may_stay_silent.value_or(false));
  if (own.target || all.target) {
    const SceneProgram& t = own.target ? own : all;
    m.target = *t.target;
    m.target_at = t.target_at;
  } else if (s.target) {
    m.target = *s.target;
    m.target_at = s.target_at;
  }
  return m;
}

void place_scene_chain(Scene* s) {
  const ScenePlacement& p = s->placement;
  WorldConfig& w = s->world;
  w.head_position = p.position_m;
  w.heading_rad = deg_to_rad(p.heading_deg);
  w.roll_rad = deg_to_rad(p.roll_deg);
  w.head_orientation.reset();
  if (!p.at_pipe_entry) return;
  w.heading_rad = 0;
  try {
    ChainModel chain = compile_chain(*s);
    place_chain_at_pipe_entry(&w, &chain, p.inset_m);
  } catch (const std::invalid_argument& e) {
    throw SceneError(s->source + ": 'placement.at: pipe_entry': " + e.what());
  }
}

void set_chain(Scene* s, const std::string& letters) {
  if (letters.empty()) throw SceneError(s->source + ": the chain is empty");
  if (letters.size() > kMaxSceneModules)
    throw SceneError(s->source + ": the chain '" + letters + "' has " + std::to_string(letters.size()) +
                     " modules, more than the limit of " + std::to_string(kMaxSceneModules));
  std::vector<SceneModule> modules;
  for (char l : letters) {
    const std::string type = module_type_for_letter(l);
    if (type.empty())
      throw SceneError(s->source + ": the chain '" + letters + "' has unknown module letter '" + std::string(1, l) +
                       "' (T touch, R rotation, H helicoidal, S support, E extension, W traveller, P passive)");
    modules.push_back(scene_module_of_type(*s, type));
  }
  s->modules = std::move(modules);
  place_scene_chain(s);
}

void set_module_param(Scene* s, int64_t module, const std::string& name, int64_t value) {
  const std::string who = s->source + ": chain[" + std::to_string(module) + "]";
  if (module < 0 || static_cast<uint64_t>(module) >= s->modules.size())
    throw SceneError(who + ": the chain has " + std::to_string(s->modules.size()) + " modules");
  set_param(&s->modules[static_cast<size_t>(module)], name, param_value(who, name, value), edited_at(*s));
}

void set_all_modules_param(Scene* s, const std::string& name, int64_t value) {
  const int32_t v = param_value(s->source + ": chain[*]", name, value);
  for (SceneModule& m : s->modules) set_param(&m, name, v, edited_at(*s));
}

void set_central_param(Scene* s, const std::string& name, int64_t value) {
  set_param(&s->central, name, param_value(s->source + ": central", name, value), edited_at(*s));
}

int set_program_param(Scene* s, const std::string& program_file, const std::string& name, int64_t value) {
  const int32_t v = param_value(s->source + ": program[" + program_file + "]", name, value);
  int n = 0;
  for (SceneModule& m : s->modules)
    if (program_file_name(m.firmware) == program_file) {
      set_param(&m, name, v, edited_at(*s));
      ++n;
    }
  if (program_file_name(s->central.firmware) == program_file) {
    set_param(&s->central, name, v, edited_at(*s));
    ++n;
  }
  return n;
}

std::string program_file_name(const std::string& program) {
  return std::filesystem::path(program).filename().string();
}

void set_duration(Scene* s, double duration_s) {
  if (!(duration_s >= 0.001 && duration_s <= 86400))
    throw SceneError(s->source + ": 'duration_s' " + std::to_string(duration_s) + " is outside 0.001 .. 86400 s");
  if (s->tick_us > std::llround(duration_s * 1e6))
    throw SceneError(s->source + ": 'physics.tick_us' (" + std::to_string(s->tick_us) +
                     " us) is longer than the run ('duration_s' " + std::to_string(duration_s) + " s)");
  s->duration_s = duration_s;
}

void set_exact_solver(Scene* s) {
  s->world.solver = WorldConfig::Solver::Exact;
  s->world.solver_iterations = WorldConfig{}.solver_iterations;
}

void set_placement(Scene* s, const ScenePlacement& p) {
  for (const auto& [key, v] : {std::pair<const char*, double>{"heading_deg", p.heading_deg}, {"roll_deg", p.roll_deg}})
    if (!(v >= -360 && v <= 360))
      throw SceneError(s->source + ": 'placement." + key + "' " + std::to_string(v) + " is outside -360 .. 360");
  if (p.at_pipe_entry && (p.heading_deg != 0 || p.position_m != ScenePlacement{}.position_m))
    throw SceneError(s->source + ": 'placement.position_m' and 'placement.heading_deg' cannot be used with "
                     "'placement.at'");
  if (!(p.inset_m >= 0 && p.inset_m <= 1000))
    throw SceneError(s->source + ": 'placement.inset_m' " + std::to_string(p.inset_m) + " is outside 0 .. 1000 m");
  s->placement = p;
  place_scene_chain(s);
}

void add_stop_rule(Scene* s, const StopRule& r) {
  if (r.along_pipe && s->world.environment.type != EnvironmentType::Pipe)
    throw SceneError(s->source + ": a stop_when rule along the pipe, but the environment is not a pipe");
  s->stop_when.push_back(r);
}

}  // namespace chainsim
