#include "optimize/individual_scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include <Eigen/Core>

#include "optimize/problem.h"
#include "scene/scene.h"
#include "scene/scene_stop.h"
#include "physics/splitmix64.h"

namespace chainsim {

namespace {

// a file named relative to base (empty: the working directory), made absolute
std::string absolute_from(const std::string& file, const std::filesystem::path& base) {
  std::filesystem::path p(file);
  if (p.is_absolute()) return file;
  return std::filesystem::absolute(base.empty() ? p : base / p).lexically_normal().string();
}

// a program name stays a name (looked up next to chainsim); a path is made
// absolute from the scene's directory, as loading the scene resolves it
void absolute_program(YAML::Node n, const std::filesystem::path& dir) {
  if (n && n.IsScalar() && n.as<std::string>().find('/') != std::string::npos)
    n = absolute_from(n.as<std::string>(), dir);
}

double number_or(const YAML::Node& n, double dflt) { return n && n.IsScalar() ? n.as<double>() : dflt; }

// an angle in (-180, 180], degrees (a perturbed heading stays in the scene's range)
double wrapped_deg(double a) {
  a = std::fmod(a, 360.0);
  if (a > 180) a -= 360;
  if (a <= -180) a += 360;
  return a;
}

// the trial's start pose: the base scene's placement moved and turned by
// start_perturbation (the scene's own checks then apply to the result)
void perturb_placement(const Problem& pr, uint64_t seed, YAML::Node* root) {
  YAML::Node pl = (*root)["placement"];
  if (!pl || !pl.IsMap()) pl = YAML::Node(YAML::NodeType::Map);
  const bool pipe_entry = static_cast<bool>(pl["at"]);
  const StartPerturbation d = start_perturbation(pr, seed, pipe_entry);
  if (d.roll_deg != 0) pl["roll_deg"] = wrapped_deg(number_or(pl["roll_deg"], 0) + d.roll_deg);
  if (pipe_entry) {
    if (d.along_m != 0) pl["inset_m"] = number_or(pl["inset_m"], 0.005) + d.along_m;
  } else {
    Eigen::Vector3d pos(0, 0, 0.02);
    if (const YAML::Node q = pl["position_m"]; q && q.IsSequence() && q.size() == 3)
      pos = Eigen::Vector3d(q[0].as<double>(), q[1].as<double>(), q[2].as<double>());
    const double h = number_or(pl["heading_deg"], 0) * M_PI / 180;
    const Eigen::Vector3d dir(std::cos(h), std::sin(h), 0), side(-std::sin(h), std::cos(h), 0);
    pos += d.along_m * dir + d.lateral_m * side;
    if (d.along_m != 0 || d.lateral_m != 0) {
      YAML::Node v(YAML::NodeType::Sequence);
      for (int i = 0; i < 3; ++i) v.push_back(std::round(pos[i] * 1e6) / 1e6);
      v.SetStyle(YAML::EmitterStyle::Flow);
      pl["position_m"] = v;
    }
    if (d.heading_deg != 0) pl["heading_deg"] = wrapped_deg(number_or(pl["heading_deg"], 0) + d.heading_deg);
  }
  (*root)["placement"] = pl;
}

}  // namespace

uint64_t evaluation_seed(uint64_t search_seed, const std::string& key) {
  uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a of the key
  for (unsigned char c : key) h = (h ^ c) * 0x100000001b3ull;
  return splitmix64(h ^ splitmix64(search_seed)) >> 2;
}

StartPerturbation start_perturbation(const Problem& pr, uint64_t seed, bool pipe_entry) {
  const PerturbSettings& b = pr.evaluation.perturb;
  // four uniform numbers in [-1, 1) from the seed alone
  auto u = [&](uint64_t k) {
    const uint64_t x = splitmix64(seed ^ splitmix64(0x70E7B0A7u + k));
    return static_cast<double>(x >> 11) * 0x1.0p-52 - 1.0;
  };
  auto round_to = [](double v, double grain) { return std::round(v / grain) * grain; };
  StartPerturbation s;
  s.along_m = round_to(pipe_entry ? b.along_m * 0.5 * (u(0) + 1.0) : b.along_m * u(0), 1e-6);
  s.lateral_m = round_to(b.lateral_m * u(1), 1e-6);
  s.heading_deg = round_to(b.heading_deg * u(2), 1e-3);
  s.roll_deg = round_to(b.roll_deg * u(3), 1e-3);
  return s;
}

std::string program_file_name(const std::string& program) {
  return std::filesystem::path(program).filename().string();
}

std::string individual_scene_yaml(const Problem& pr, const Phenotype& p, uint64_t seed, const std::string& solver,
                                  const std::string& target_override) {
  const std::string& target = !target_override.empty() ? target_override : pr.evaluation.target;
  YAML::Node root;
  try {
    root = YAML::Load(pr.scene_text);
  } catch (const YAML::Exception& e) {
    throw SceneError(pr.scene_file + ": " + e.what());
  }
  const std::filesystem::path dir = std::filesystem::path(pr.scene_file).parent_path();
  root["seed"] = seed;
  if (pr.evaluation.duration_s > 0) root["duration_s"] = pr.evaluation.duration_s;
  if (solver == "exact") {
    root["physics"]["solver"] = "exact";
    root["physics"].remove("solver_iterations");
  }
  if (!pr.evaluation.stop_when.empty()) {
    YAML::Node rules = root["stop_when"];
    if (!rules || !rules.IsSequence()) rules = YAML::Node(YAML::NodeType::Sequence);
    for (const StopRule& r : pr.evaluation.stop_when) rules.push_back(stop_rule_yaml(r));
    root["stop_when"] = rules;
  }
  if (pr.evaluation.perturb.any()) perturb_placement(pr, seed, &root);

  // files the scene names, absolute
  if (YAML::Node mt = root["module_types"]; mt && mt.IsMap())
    for (auto kv : mt)
      if (kv.second.IsScalar()) kv.second = absolute_from(kv.second.as<std::string>(), dir);
  if (YAML::Node env = root["environment"]; env && env.IsMap())
    if (YAML::Node mesh = env["mesh"]; mesh && mesh.IsMap() && mesh["file"] && mesh["file"].IsScalar())
      mesh["file"] = absolute_from(mesh["file"].as<std::string>(), dir);
  if (YAML::Node c = root["central"]; c && c.IsMap()) absolute_program(c["program"], dir);
  if (YAML::Node pg = root["programs"]; pg && pg.IsMap())
    for (auto kv : pg)
      if (kv.second.IsMap()) absolute_program(kv.second["firmware"], dir);

  // --target: every endpoint on it, whatever the scene says module by module
  if (!target.empty()) {
    root["target"] = target;
    if (YAML::Node c = root["central"]; c && c.IsMap()) c.remove("target");
    if (YAML::Node pg = root["programs"]; pg && pg.IsMap())
      for (auto kv : pg)
        if (kv.second.IsMap()) kv.second.remove("target");
  }

  // the chain: the genome's letters, or the base scene's
  bool module_params = false;
  for (const auto& g : pr.genome.params) module_params |= g.scope != ParamGene::Scope::Central;
  if (pr.genome.has_chain) root["chain"] = p.chain;
  YAML::Node chain = root["chain"];
  if (module_params && chain.IsScalar()) {  // parameters need the list form
    YAML::Node list(YAML::NodeType::Sequence);
    for (char l : chain.as<std::string>()) {
      YAML::Node m;
      m["type"] = module_type_for_letter(l);
      list.push_back(m);
    }
    root["chain"] = list;
    chain = root["chain"];
  }
  if (chain.IsSequence())
    for (size_t i = 0; i < chain.size(); ++i)
      if (chain[i].IsMap()) {
        absolute_program(chain[i]["firmware"], dir);
        if (!target.empty()) chain[i].remove("target");
      }

  // program[NAME].param: the endpoints whose program (as written, or their
  // module type's) has that file name, from the scene as loaded
  std::vector<std::string> programs;  // per chain module, then the central control's
  for (const ParamGene& g : pr.genome.params)
    if (g.scope == ParamGene::Scope::Program) {
      YAML::Emitter e;
      e << root;
      const Scene s = load_scene_text(std::string(e.c_str()) + "\n", pr.scene_file);
      for (const SceneModule& m : s.modules) programs.push_back(program_file_name(m.firmware));
      programs.push_back(program_file_name(s.central.firmware));
      break;
    }

  for (size_t k = 0; k < pr.genome.params.size() && k < p.values.size(); ++k) {
    const ParamGene& g = pr.genome.params[k];
    const int64_t v = p.values[k];
    switch (g.scope) {
      case ParamGene::Scope::Central: root["central"]["params"][g.name] = v; break;
      case ParamGene::Scope::Module:
        if (static_cast<size_t>(g.module) >= chain.size())
          throw SceneError(pr.file + ": " + g.target + ": the chain has " + std::to_string(chain.size()) + " modules");
        chain[static_cast<size_t>(g.module)]["params"][g.name] = v;
        break;
      case ParamGene::Scope::AllModules:
        for (size_t i = 0; i < chain.size(); ++i) chain[i]["params"][g.name] = v;
        break;
      case ParamGene::Scope::Program:
        for (size_t i = 0; i < chain.size() && i < programs.size(); ++i)
          if (programs[i] == g.program) chain[i]["params"][g.name] = v;
        if (!programs.empty() && programs.back() == g.program) root["central"]["params"][g.name] = v;
        break;
    }
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace chainsim
