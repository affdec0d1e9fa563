// What a search optimises: named measures of a finished run (distance along
// an axis or the pipe, mean speed, the time a point is passed, how far short
// of a point the run stayed, energy, energy per metre, the number of
// modules), the objective as a weighted sum of them, and constraints on them.
// A run that faults or breaks a constraint gets the problem's failed fitness
// and the reason.
#pragma once

#include <Eigen/Core>

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "environment/pipe_progress.h"
#include "optimize/run_outcome.h"
#include "optimize/trial_fitness.h"

namespace chainsim {

struct MeasureSpec {
  enum class Kind { Distance, Speed, TimeToReach, Shortfall, Energy, EnergyPerM, Modules };
  enum class Of { Head, Tail, Chain };   // Chain: the mass centre from summary.json
  std::string name;                      // history column and the key objective/constraints use
  Kind kind = Kind::Distance;
  Of of = Of::Head;
  bool along_pipe = false;               // along the pipe's axis, else along `axis`
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit vector
  double reach_m = 0;                    // TimeToReach, Shortfall: position along `along` to reach
  double never_s = std::numeric_limits<double>::infinity();  // TimeToReach: the value if never reached
};

struct ObjectiveSpec {
  bool maximize = true;
  std::vector<std::pair<int, double>> weights;  // (measure index, weight)
  double failed_fitness = 0;                    // what a failed run scores
};

struct ConstraintSpec {
  int measure = -1;
  std::optional<double> min, max;
};

struct Score {
  std::vector<double> measures;  // one per MeasureSpec (infinity: never reached, unless never_s)
  double fitness = 0;            // in the objective's sense
  bool failed = false;
  std::string why;               // fault or broken constraint
  std::string early_stop;        // a stop_when rule ended the run early: what it saw
  // over the trials of combine_trials: how many, and their fitness's sample
  // standard deviation (NaN for one trial), lowest and highest
  int trials = 1;
  double fitness_sd = std::numeric_limits<double>::quiet_NaN();
  double fitness_min = std::numeric_limits<double>::quiet_NaN();
  double fitness_max = std::numeric_limits<double>::quiet_NaN();
};

// the value of one measure; pipe is needed for along_pipe measures
double measure_value(const MeasureSpec& m, const RunOutcome& run, const PipeProgress* pipe);

// measures, constraints and fitness of a run
Score score_run(const std::vector<MeasureSpec>& measures, const ObjectiveSpec& objective,
                const std::vector<ConstraintSpec>& constraints, const RunOutcome& run,
                const PipeProgress* pipe);

// the score of a run that could not be measured at all (bad scene, no outputs)
Score failed_score(size_t n_measures, const ObjectiveSpec& objective, const std::string& why);

// the score of an individual's trials: the first failed one, else the
// measures' means and a fitness by `how`: Mean, the objective of the
// measures' means; Worst, the worst trial's fitness; Quantile, the q-quantile
// of the trials' fitnesses ordered worst to best (q = 0 the worst, 1 the best,
// linear between neighbours). Always the spread: sd, min and max.
// `asked`: the trials the individual was to run (a failed one ends it
// early; 0: as many as given), for the failure's words "trial 2 of 3"
Score combine_trials(const std::vector<Score>& trials, const ObjectiveSpec& objective, TrialFitness how = TrialFitness::Mean,
                     double q = 0.5, int asked = 0);

// true when fitness a is better than b in the objective's sense
inline bool better_fitness(const ObjectiveSpec& o, double a, double b) { return o.maximize ? a > b : a < b; }

}  // namespace chainsim
