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
#include "optimize/pipe_progress.h"

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
};

struct EvaluationSettings {
  double duration_s = -1;            // < 0: the base scene's
  double module_timeout_s = 10;      // chainsim run --module-timeout
  int repeats = 1;                   // runs per individual, each with its own seed; the mean is scored
  std::string target;                // "": as the scene says; native or pic for every endpoint (--target)
};

struct Problem {
  std::string file;                  // the problem file as given
  std::string text;                  // its text
  std::string name;
  std::string scene_file;            // the base scene, resolved against the problem's directory
  std::string scene_text;
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
