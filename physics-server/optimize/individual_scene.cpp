#include "optimize/individual_scene.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "optimize/problem.h"
#include "scene/scene.h"
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

}  // namespace

uint64_t evaluation_seed(uint64_t search_seed, const std::string& key) {
  uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a of the key
  for (unsigned char c : key) h = (h ^ c) * 0x100000001b3ull;
  return splitmix64(h ^ splitmix64(search_seed)) >> 2;
}

std::string individual_scene_yaml(const Problem& pr, const Phenotype& p, uint64_t seed) {
  YAML::Node root;
  try {
    root = YAML::Load(pr.scene_text);
  } catch (const YAML::Exception& e) {
    throw SceneError(pr.scene_file + ": " + e.what());
  }
  const std::filesystem::path dir = std::filesystem::path(pr.scene_file).parent_path();
  root["seed"] = seed;
  if (pr.evaluation.duration_s > 0) root["duration_s"] = pr.evaluation.duration_s;

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
  if (!pr.evaluation.target.empty()) {
    root["target"] = pr.evaluation.target;
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
        if (!pr.evaluation.target.empty()) chain[i].remove("target");
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
    }
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace chainsim
