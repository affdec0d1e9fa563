// A design-search problem file (docs/optimize.md): the base scene, the
// genome, the measures, objective and constraints, the GA's settings and how
// each individual is run. Read strictly: an unknown key, a wrong type or a
// value out of range is an error naming file:line:column and the key.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "optimize/genome.h"
#include "optimize/objective.h"
#include "environment/pipe_progress.h"
#include "scene/scene.h"

namespace chainsim {

struct ProblemError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// pagmo::sga's settings (names as in pagmo)
struct GaSettings {
  int population = 40;               // the paper's
  int generations = 20;              // after the initial population
  uint64_t seed = 1;
  std::string crossover = "single";  // single | exponential | binomial
  double crossover_probability = 0.9;
  std::string mutation = "uniform";  // uniform | gaussian
  double mutation_probability = -1;  // < 0: 1 / number of genes
  double mutation_width = 0.1;       // gaussian: sigma as a fraction of the gene's range
  std::string selection = "tournament";  // tournament | truncated
  int selection_size = 2;            // tournament size, or how many the truncation keeps
  // several populations evolving apart (search: ga only): island i's GA is
  // seeded from the search seed and i; after every migration_every-th
  // generation island i's best `migrants` replace the worst of island i + 1
  // (a ring), where they are better
  int islands = 1;
  int migration_every = 5;
  int migrants = 1;
};

// a small change of the start pose for each trial, uniform within these
// bounds and drawn from the trial's seed (docs/optimize.md, "evaluation")
struct PerturbSettings {
  double along_m = 0;      // along the chain's axis (in a pipe: deeper only, 0..along_m)
  double lateral_m = 0;    // sideways, horizontal (open ground and terrain only)
  double heading_deg = 0;  // about z (open ground and terrain only)
  double roll_deg = 0;     // about the chain's own axis
  bool any() const { return along_m > 0 || lateral_m > 0 || heading_deg > 0 || roll_deg > 0; }
};

struct EvaluationSettings {
  double duration_s = -1;            // < 0: the base scene's
  double module_timeout_s = 10;      // chainsim run --module-timeout
  // runs per individual, each with its own seed; 0: auto (kAutoProbeTrials
  // for the first generation, kept if any individual's fitness varied
  // between its trials, else 1 from then on)
  int trials = 0;
  TrialFitness fitness = TrialFitness::Mean;
  double quantile = 0.5;             // TrialFitness::Quantile: 0 the worst trial, 1 the best
  PerturbSettings perturb;
  std::vector<StopRule> stop_when;   // copied into every individual's scene
  bool stop_on_constraints = true;   // a time_to_reach constraint's max also stops the run
  std::string target;                // "": as the scene says; native or pic for every endpoint (--target)
  // where every evaluation looks for programs first (DIR[:DIR...], absolute),
  // before next to chainsim: --firmware-dir, not a key of the problem file
  std::string firmware_dir;
};

constexpr int kAutoProbeTrials = 3;

struct Problem {
  std::string file;                  // the problem file as given
  std::string text;                  // its text
  std::string name;
  std::string scene_file;            // the base scene, resolved against the problem's directory
  std::string scene_text;
  std::shared_ptr<const Scene> scene;  // the base scene as loaded (individual_scene.h edits a copy)
  int base_modules = 0;              // modules in the base scene's chain
  bool exhaustive = false;           // search: exhaustive (every individual, in gene order)
  GenomeSpec genome;
  std::vector<MeasureSpec> measures;
  ObjectiveSpec objective;
  std::vector<ConstraintSpec> constraints;
  GaSettings ga;
  EvaluationSettings evaluation;
  std::shared_ptr<const PipeProgress> pipe;  // the base scene's pipe, if it is one
};

// reads a problem file; throws ProblemError ("file:line:column: ...")
Problem load_problem_file(const std::string& path);
// the same from text; file names it in errors and resolves the scene path
Problem load_problem_text(const std::string& text, const std::string& file);

}  // namespace chainsim
