#include "optimize/problem.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <climits>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "environment/pipe_path.h"
#include "readers/safe_text.h"
#include "optimize/individual_scene.h"
#include "scene/scene.h"
#include "scene/scene_stop.h"
#include "scene/scene_yaml.h"

namespace chainsim {

namespace {

int64_t get_int(const SceneYaml& y, const YAML::Node& map, const std::string& key, int64_t dflt, int64_t lo,
                int64_t hi, const std::string& path) {
  const YAML::Node n = map[key];
  if (!n) return dflt;
  int64_t v = 0;
  try {
    v = n.as<int64_t>();
  } catch (const YAML::Exception&) {
    y.fail(n, "'" + path + "." + key + "' must be an integer");
  }
  if (v < lo || v > hi)
    y.fail(n, "'" + path + "." + key + "' = " + std::to_string(v) + " is out of range [" + std::to_string(lo) +
                  ", " + std::to_string(hi) + "]");
  return v;
}

bool is_identifier(const std::string& s, size_t max_len) {
  if (s.empty() || s.size() > max_len) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

void load_chain_genome(const SceneYaml& y, const YAML::Node& n, ChainGenome* c) {
  y.keys(n, "genome.chain", {"positions", "min_length"});
  const YAML::Node pos = n["positions"];
  if (!pos) y.fail(n, "'genome.chain' needs 'positions' (a list such as [T, RH, RH])");
  if (!pos.IsSequence() || pos.size() == 0 || pos.size() > 64)
    y.fail(pos, "'genome.chain.positions' must be a list of 1 to 64 strings of module letters");
  for (size_t i = 0; i < pos.size(); ++i) {
    const std::string p = "genome.chain.positions[" + std::to_string(i) + "]";
    if (!pos[i].IsScalar() || pos[i].as<std::string>().empty())
      y.fail(pos[i], "'" + p + "' must be a string of module letters, e.g. RH");
    const std::string letters = pos[i].as<std::string>();
    for (size_t k = 0; k < letters.size(); ++k) {
      if (module_type_for_letter(letters[k]).empty())
        y.fail(pos[i], "'" + p + "' has unknown module letter '" + letters[k] +
                           "' (T touch, R rotation, H helicoidal, S support, E extension, W traveller, P passive)");
      if (letters.find(letters[k]) != k) y.fail(pos[i], "'" + p + "' has the letter '" + letters[k] + "' twice");
    }
    c->positions.push_back(letters);
  }
  const int64_t npos = static_cast<int64_t>(c->positions.size());
  c->min_length = static_cast<int>(get_int(y, n, "min_length", npos, 1, npos, "genome.chain"));
}

void load_param_gene(const SceneYaml& y, const YAML::Node& n, const std::string& p, bool has_chain,
                     int base_modules, ParamGene* g) {
  y.keys(n, p, {"target", "min", "max", "step"});
  for (const char* k : {"target", "min", "max"})
    if (!n[k]) y.fail(n, "'" + p + "' needs '" + k + "'");
  g->target = y.text(n, "target", "", p);
  g->where = y.where(n);
  const std::string& t = g->target;
  const size_t dot = t.rfind('.');
  const std::string head = dot == std::string::npos ? "" : t.substr(0, dot);
  g->name = dot == std::string::npos ? "" : t.substr(dot + 1);
  const std::string form = "'" + p + ".target' '" + t +
                           "' must be central.NAME, chain[INDEX].NAME, chain[*].NAME or program[PROGRAM].NAME (NAME: 1 "
                           "to 15 letters, digits or _; PROGRAM: a program's file name, e.g. fw-rotation)";
  if (!is_identifier(g->name, 15)) y.fail(n["target"], form);
  if (head == "central") {
    g->scope = ParamGene::Scope::Central;
  } else if (head == "chain[*]") {
    g->scope = ParamGene::Scope::AllModules;
  } else if (head.size() > 9 && head.rfind("program[", 0) == 0 && head.back() == ']') {
    g->scope = ParamGene::Scope::Program;
    g->program = head.substr(8, head.size() - 9);
    if (!is_path_name(g->program)) y.fail(n["target"], form);
  } else if (head.size() > 7 && head.rfind("chain[", 0) == 0 && head.back() == ']') {
    const std::string idx = head.substr(6, head.size() - 7);
    if (idx.empty() || idx.size() > 2 || idx.find_first_not_of("0123456789") != std::string::npos)
      y.fail(n["target"], form);
    g->scope = ParamGene::Scope::Module;
    g->module = std::stoi(idx);
    if (has_chain)
      y.fail(n["target"], "'" + p + ".target' '" + t +
                              "': a module index means nothing when the genome chooses the chain; use chain[*]");
    if (g->module >= base_modules)
      y.fail(n["target"], "'" + p + ".target' '" + t + "': the base scene's chain has modules 0.." +
                              std::to_string(base_modules - 1));
  } else {
    y.fail(n["target"], form);
  }
  g->min = get_int(y, n, "min", 0, INT32_MIN, INT32_MAX, p);
  g->max = get_int(y, n, "max", 0, INT32_MIN, INT32_MAX, p);
  g->step = get_int(y, n, "step", 1, 1, INT32_MAX, p);
  if (g->max < g->min) y.fail(n["max"], "'" + p + ".max' is below '" + p + ".min'");
  if ((g->max - g->min) % g->step != 0)
    y.fail(n["max"], "'" + p + ".max' must be min plus a whole number of steps (" + std::to_string(g->min) +
                         " + k * " + std::to_string(g->step) + ")");
}

MeasureSpec load_measure(const SceneYaml& y, const YAML::Node& n, const std::string& name, bool has_pipe) {
  const std::string p = "measures." + name;
  MeasureSpec m;
  m.name = name;
  if (!n.IsMap()) y.fail(n, "'" + p + "' must be a mapping with a 'kind'");
  if (!n["kind"])
    y.fail(n, "'" + p + "' needs a 'kind' (distance, speed, time_to_reach, shortfall, energy, energy_per_m, modules)");
  const std::string kind = y.choice(
      n, "kind", "", {"distance", "speed", "time_to_reach", "shortfall", "energy", "energy_per_m", "modules"}, p);
  if (kind == "energy" || kind == "modules") {
    y.keys(n, p, {"kind"});
    m.kind = kind == "energy" ? MeasureSpec::Kind::Energy : MeasureSpec::Kind::Modules;
    return m;
  }
  m.kind = kind == "distance"        ? MeasureSpec::Kind::Distance
           : kind == "speed"         ? MeasureSpec::Kind::Speed
           : kind == "time_to_reach" ? MeasureSpec::Kind::TimeToReach
           : kind == "shortfall"     ? MeasureSpec::Kind::Shortfall
                                     : MeasureSpec::Kind::EnergyPerM;
  const bool to_reach = m.kind == MeasureSpec::Kind::TimeToReach || m.kind == MeasureSpec::Kind::Shortfall;
  std::set<std::string> keys = {"kind", "of", "along"};
  if (to_reach) keys.insert("reach_m");
  if (m.kind == MeasureSpec::Kind::TimeToReach) keys.insert("never_s");
  y.keys(n, p, keys);
  if (to_reach) {
    if (!n["reach_m"]) y.fail(n, "'" + p + "' needs 'reach_m' (the position along 'along' to reach, m)");
    m.reach_m = y.number(n, "reach_m", 0, -1e6, 1e6, p);
  }
  if (m.kind == MeasureSpec::Kind::TimeToReach && n["never_s"]) m.never_s = y.number(n, "never_s", 0, 0, 1e9, p);
  const bool chain_ok = !to_reach;
  const std::string of = chain_ok ? y.choice(n, "of", "head", {"head", "tail", "chain"}, p)
                                  : y.choice(n, "of", "head", {"head", "tail"}, p);
  m.of = of == "head" ? MeasureSpec::Of::Head : of == "tail" ? MeasureSpec::Of::Tail : MeasureSpec::Of::Chain;
  const YAML::Node a = n["along"];
  if (a && a.IsSequence()) {
    m.axis = y.vec3(n, "along", m.axis, p);
    if (m.axis.norm() < 1e-12) y.fail(a, "'" + p + ".along' must not be the zero vector");
    m.axis.normalize();
  } else {
    const std::string along = y.choice(n, "along", "x", {"x", "y", "z", "pipe"}, p);
    m.along_pipe = along == "pipe";
    m.axis = along == "y" ? Eigen::Vector3d::UnitY() : along == "z" ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    if (m.along_pipe && !has_pipe) y.fail(a, "'" + p + ".along' is pipe but the base scene's environment is not a pipe");
    if (m.along_pipe && m.of == MeasureSpec::Of::Chain)
      y.fail(n["of"], "'" + p + "': 'of: chain' is measured along an axis only (use head or tail along the pipe)");
  }
  return m;
}

int measure_index(const SceneYaml& y, const YAML::Node& at, const std::vector<MeasureSpec>& ms,
                  const std::string& name, const std::string& path) {
  std::string known;
  for (size_t i = 0; i < ms.size(); ++i) {
    if (ms[i].name == name) return static_cast<int>(i);
    known += (known.empty() ? "" : ", ") + ms[i].name;
  }
  y.fail(at, "'" + path + "' names measure '" + name + "', which is not in 'measures' (known: " + known + ")");
}

void load_objective(const SceneYaml& y, const YAML::Node& n, Problem* pr) {
  y.keys(n, "objective", {"maximize", "minimize", "failed_fitness"});
  const YAML::Node mx = n["maximize"], mn = n["minimize"];
  if (!mx == !mn) y.fail(n, "'objective' needs exactly one of 'maximize' and 'minimize'");
  pr->objective.maximize = static_cast<bool>(mx);
  const YAML::Node w = mx ? mx : mn;
  const std::string path = std::string("objective.") + (mx ? "maximize" : "minimize");
  if (w.IsScalar()) {
    pr->objective.weights.push_back({measure_index(y, w, pr->measures, w.as<std::string>(), path), 1.0});
  } else if (w.IsMap() && w.size() > 0) {
    for (const auto& kv : w) {
      const std::string name = kv.first.as<std::string>();
      const int k = measure_index(y, kv.first, pr->measures, name, path);
      double weight = 0;
      try {
        weight = kv.second.as<double>();
      } catch (const YAML::Exception&) {
        y.fail(kv.second, "'" + path + "." + name + "' must be a number (the weight)");
      }
      if (!std::isfinite(weight)) y.fail(kv.second, "'" + path + "." + name + "' must be finite");
      pr->objective.weights.push_back({k, weight});
    }
  } else {
    y.fail(w, "'" + path + "' must be a measure name or a mapping {measure: weight}");
  }
  if (!n["failed_fitness"] && !pr->objective.maximize)
    y.fail(n, "'objective' minimizes, so it needs 'failed_fitness' (a value worse than any real one)");
  pr->objective.failed_fitness = y.number(n, "failed_fitness", 0.0, -1e300, 1e300, "objective");
}

void load_constraints(const SceneYaml& y, const YAML::Node& n, Problem* pr) {
  if (!n.IsSequence()) y.fail(n, "'constraints' must be a list of {measure, min, max}");
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string p = "constraints[" + std::to_string(i) + "]";
    const YAML::Node c = n[i];
    y.keys(c, p, {"measure", "min", "max"});
    if (!c["measure"]) y.fail(c, "'" + p + "' needs 'measure'");
    if (!c["min"] && !c["max"]) y.fail(c, "'" + p + "' needs 'min' or 'max'");
    ConstraintSpec cs;
    cs.measure = measure_index(y, c["measure"], pr->measures, y.text(c, "measure", "", p), p + ".measure");
    if (c["min"]) cs.min = y.number(c, "min", 0, -1e300, 1e300, p);
    if (c["max"]) cs.max = y.number(c, "max", 0, -1e300, 1e300, p);
    if (cs.min && cs.max && *cs.min > *cs.max)
      y.fail(c["max"], "'" + p + "': min " + std::to_string(*cs.min) + " is above max " + std::to_string(*cs.max) +
                           ": no run can keep it");
    pr->constraints.push_back(cs);
  }
}

void load_ga(const SceneYaml& y, const YAML::Node& n, GaSettings* g) {
  const std::string p = "ga";
  y.keys(n, p,
         {"population", "generations", "seed", "crossover", "crossover_probability", "mutation",
          "mutation_probability", "mutation_width", "selection", "selection_size", "islands", "migration_every",
          "migrants"});
  g->population = static_cast<int>(get_int(y, n, "population", g->population, 2, 100000, p));
  g->generations = static_cast<int>(get_int(y, n, "generations", g->generations, 0, 1000000, p));
  g->seed = static_cast<uint64_t>(get_int(y, n, "seed", 1, 0, INT64_MAX, p));
  g->crossover = y.choice(n, "crossover", g->crossover, {"single", "exponential", "binomial"}, p);
  g->crossover_probability = y.number(n, "crossover_probability", g->crossover_probability, 0, 1, p);
  g->mutation = y.choice(n, "mutation", g->mutation, {"uniform", "gaussian"}, p);
  g->mutation_probability = y.number(n, "mutation_probability", -1, 0, 1, p);
  if (!n["mutation_probability"]) g->mutation_probability = -1;
  g->mutation_width = y.number(n, "mutation_width", g->mutation_width, 0, 1, p);
  g->selection = y.choice(n, "selection", g->selection, {"tournament", "truncated"}, p);
  g->selection_size = static_cast<int>(get_int(y, n, "selection_size", g->selection_size, 1, 100000, p));
  g->islands = static_cast<int>(get_int(y, n, "islands", g->islands, 1, 10000, p));
  g->migration_every = static_cast<int>(get_int(y, n, "migration_every", g->migration_every, 1, 1000000, p));
  g->migrants = static_cast<int>(get_int(y, n, "migrants", g->migrants, 1, 100000, p));
  if (g->migrants >= g->population)
    y.fail(n["migrants"] ? n["migrants"] : n, "'ga.migrants' (" + std::to_string(g->migrants) +
                                                  ") must be smaller than 'ga.population' (" +
                                                  std::to_string(g->population) + ")");
  if (g->selection_size > g->population)
    y.fail(n["selection_size"] ? n["selection_size"] : n,
           "'ga.selection_size' (" + std::to_string(g->selection_size) + ") is larger than 'ga.population' (" +
               std::to_string(g->population) + ")");
}

void load_perturb(const SceneYaml& y, const YAML::Node& n, bool pipe_entry, PerturbSettings* p) {
  const std::string path = "evaluation.perturb";
  if (!n.IsMap()) y.fail(n, "'" + path + "' must be a mapping {along_m, lateral_m, heading_deg, roll_deg}");
  y.keys(n, path, {"along_m", "lateral_m", "heading_deg", "roll_deg"});
  p->along_m = y.number(n, "along_m", 0, 0, 1, path);
  p->lateral_m = y.number(n, "lateral_m", 0, 0, 1, path);
  p->heading_deg = y.number(n, "heading_deg", 0, 0, 180, path);
  p->roll_deg = y.number(n, "roll_deg", 0, 0, 180, path);
  if (pipe_entry)
    for (const char* k : {"lateral_m", "heading_deg"})
      if (n[k])
        y.fail(n[k], "'" + path + "." + k + "': the base scene places the chain at the pipe's entry, where only "
                     "along_m (deeper in) and roll_deg apply");
}

void load_evaluation(const SceneYaml& y, const YAML::Node& e, Problem* pr) {
  const std::string path = "evaluation";
  if (e["repeats"])
    y.fail(e["repeats"], "'evaluation.repeats' is now 'evaluation.trials' (the same: runs per individual, each "
                         "with its own seed)");
  y.keys(e, path,
         {"duration_s", "module_timeout_s", "trials", "fitness", "quantile", "perturb", "stop_when",
          "stop_on_constraints"});
  EvaluationSettings& ev = pr->evaluation;
  ev.duration_s = y.number(e, "duration_s", -1, 0.001, 86400, path);
  if (!e["duration_s"]) ev.duration_s = -1;
  ev.module_timeout_s = y.number(e, "module_timeout_s", 10, 0.001, 86400, path, true);
  if (const YAML::Node t = e["trials"]; t && t.IsScalar() && t.as<std::string>() == "auto") ev.trials = 0;
  else if (t) ev.trials = static_cast<int>(get_int(y, e, "trials", 1, 1, 1000, path));
  const std::string f = y.choice(e, "fitness", "mean", {"mean", "worst", "quantile"}, path);
  ev.fitness = f == "mean" ? TrialFitness::Mean : f == "worst" ? TrialFitness::Worst : TrialFitness::Quantile;
  if (ev.fitness == TrialFitness::Quantile && !e["quantile"])
    y.fail(e, "'evaluation.fitness: quantile' needs 'evaluation.quantile' (0: the worst trial, 1: the best)");
  if (ev.fitness != TrialFitness::Quantile && e["quantile"])
    y.fail(e["quantile"], "'evaluation.quantile' applies to 'fitness: quantile' only");
  ev.quantile = y.number(e, "quantile", 0.5, 0, 1, path);
  const bool pipe_entry = pr->scene->placement.at_pipe_entry;
  if (const YAML::Node p = e["perturb"]) load_perturb(y, p, pipe_entry, &ev.perturb);
  if (const YAML::Node st = e["stop_when"]) {
    Scene tmp;
    if (pr->pipe) tmp.world.environment.type = EnvironmentType::Pipe;
    load_scene_stop_when(y.file(), st, &tmp, "evaluation.stop_when");
    ev.stop_when = tmp.stop_when;
  }
  ev.stop_on_constraints = y.flag(e, "stop_on_constraints", true, path);
}

// a constraint `time_to_reach <= max` is broken once max has passed without
// the mark: the run can stop there (its measure is then never_s or inf
// either way, and the constraint fails either way)
void add_constraint_stops(Problem* pr) {
  for (const ConstraintSpec& c : pr->constraints) {
    const MeasureSpec& m = pr->measures[static_cast<size_t>(c.measure)];
    if (m.kind != MeasureSpec::Kind::TimeToReach || !c.max) continue;
    // a run that never reaches scores never_s: if that is within the bound,
    // not reaching is no failure and nothing can be decided early
    if (std::isfinite(m.never_s) && m.never_s <= *c.max) continue;
    // a bound no run reaches (a scene lasts at most 86400 s) stops nothing
    if (!(*c.max >= 0 && *c.max <= 86400)) continue;
    StopRule r;
    r.kind = StopRule::Kind::NotReached;
    r.tail = m.of == MeasureSpec::Of::Tail;
    r.along_pipe = m.along_pipe;
    r.axis = m.axis;
    r.reach_m = m.reach_m;
    r.by_s = *c.max;
    pr->evaluation.stop_when.push_back(r);
  }
}

// a regular file of at most 16 MiB (the strict reader's bounds), else a ProblemError naming it
std::string read_text(const std::string& path, const std::string& what) {
  try {
    return SceneYaml{path}.read_file(what);
  } catch (const SceneError& e) {
    throw ProblemError(e.what());
  }
}

void load_base_scene(const SceneYaml& y, const YAML::Node& root, Problem* pr) {
  if (!root["scene"]) y.fail(root, "missing key 'scene' (the base scene file, relative to this file)");
  const std::string given = y.text(root, "scene", "", "problem");
  std::filesystem::path sp(given);
  const std::filesystem::path dir = std::filesystem::path(pr->file).parent_path();
  if (sp.is_relative() && !dir.empty()) sp = dir / sp;
  pr->scene_file = sp.lexically_normal().string();
  try {
    pr->scene_text = SceneYaml{pr->scene_file}.read_file("base scene");
  } catch (const SceneError& e) {
    y.fail(root["scene"], std::string("'scene': ") + e.what());
  }
  Scene scene;
  try {
    scene = load_scene_text(pr->scene_text, pr->scene_file);
  } catch (const SceneError& e) {
    y.fail(root["scene"], std::string("'scene': ") + e.what());
  }
  pr->base_modules = static_cast<int>(scene.modules.size());
  if (scene.world.environment.type == EnvironmentType::Pipe)
    pr->pipe = std::make_shared<PipeProgress>(layout_pipe(scene.world.environment.pipe));
  pr->scene = std::make_shared<const Scene>(std::move(scene));
}

Problem load(const std::string& text, const std::string& file) {
  const SceneYaml y{file};
  Problem pr;
  pr.file = file;
  pr.text = text;
  // a syntax error, a second document, a key given twice: named where
  const YAML::Node root = y.parse(text);
  if (!root || !root.IsMap()) throw ProblemError(file + ": a problem file must be a YAML mapping");
  y.keys(root, "problem",
         {"name", "scene", "search", "genome", "measures", "objective", "constraints", "ga", "evaluation"});
  pr.name = y.text(root, "name", std::filesystem::path(file).stem().string(), "problem");
  load_base_scene(y, root, &pr);
  pr.exhaustive = y.choice(root, "search", "ga", {"ga", "exhaustive"}, "problem") == "exhaustive";

  const YAML::Node g = root["genome"];
  if (!g) y.fail(root, "missing key 'genome' (a 'chain' and/or 'params')");
  y.keys(g, "genome", {"chain", "params"});
  if (!g["chain"] && !g["params"]) y.fail(g, "'genome' needs a 'chain' or 'params' (or both)");
  if (g["chain"]) {
    pr.genome.has_chain = true;
    load_chain_genome(y, g["chain"], &pr.genome.chain);
  }
  if (const YAML::Node ps = g["params"]) {
    if (!ps.IsSequence()) y.fail(ps, "'genome.params' must be a list of {target, min, max, step}");
    std::set<std::string> seen;
    for (size_t i = 0; i < ps.size(); ++i) {
      ParamGene pg;
      load_param_gene(y, ps[i], "genome.params[" + std::to_string(i) + "]", pr.genome.has_chain,
                      pr.base_modules, &pg);
      if (!seen.insert(pg.target).second) y.fail(ps[i], "'" + pg.target + "' is in 'genome.params' twice");
      pr.genome.params.push_back(pg);
    }
  }
  if (pr.genome.gene_count() == 0) y.fail(g, "'genome' leaves nothing to choose (every position fixed, no params)");

  const YAML::Node ms = root["measures"];
  if (!ms || !ms.IsMap() || ms.size() == 0)
    y.fail(ms ? ms : root, "'measures' must be a mapping of name: {kind, ...} with at least one measure");
  for (const auto& kv : ms) {
    const std::string name = kv.first.as<std::string>();
    if (!is_identifier(name, 40)) y.fail(kv.first, "measure name '" + name + "' must be letters, digits or _");
    pr.measures.push_back(load_measure(y, kv.second, name, pr.pipe != nullptr));
  }
  if (!root["objective"]) y.fail(root, "missing key 'objective'");
  load_objective(y, root["objective"], &pr);
  if (root["constraints"]) load_constraints(y, root["constraints"], &pr);
  if (root["ga"]) load_ga(y, root["ga"], &pr.ga);
  if (pr.exhaustive && pr.ga.islands > 1)
    y.fail(root["ga"]["islands"], "'ga.islands' applies to 'search: ga' (an exhaustive search has no populations)");
  if (const YAML::Node e = root["evaluation"]) load_evaluation(y, e, &pr);
  if (pr.evaluation.stop_on_constraints) add_constraint_stops(&pr);

  // the genome must make valid scenes: try the first individual
  try {
    const Phenotype first = decode_genes(pr.genome, std::vector<int64_t>(pr.genome.gene_count(), 0));
    load_scene_text(individual_scene_yaml(pr, first, 1), file + " (genome applied to " + pr.scene_file + ")");
  } catch (const SceneError& e) {
    y.fail(g, std::string("'genome': the first individual's scene is not valid: ") + e.what());
  }
  return pr;
}

}  // namespace

Problem load_problem_text(const std::string& text, const std::string& file) {
  try {
    return load(text, file);
  } catch (const SceneError& e) {
    throw ProblemError(e.what());
  } catch (const YAML::Exception& e) {
    throw ProblemError(file + ": " + e.what());
  }
}

Problem load_problem_file(const std::string& path) { return load_problem_text(read_text(path, "problem file"), path); }

}  // namespace chainsim
