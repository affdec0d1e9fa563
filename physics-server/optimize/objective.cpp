#include "optimize/objective.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "text/number_text.h"

namespace chainsim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

const std::vector<Eigen::Vector3d>& track(const MeasureSpec& m, const RunOutcome& r) {
  return m.of == MeasureSpec::Of::Tail ? r.tail : r.head;
}

// position of the track point along the measure's direction
double along(const MeasureSpec& m, const Eigen::Vector3d& p, const PipeProgress* pipe) {
  return m.along_pipe ? pipe->at(p) : p.dot(m.axis);
}

double distance(const MeasureSpec& m, const RunOutcome& r, const PipeProgress* pipe) {
  if (m.of == MeasureSpec::Of::Chain) return r.chain_displacement.dot(m.axis);
  const auto& tr = track(m, r);
  if (tr.empty()) return 0;
  return along(m, tr.back(), pipe) - along(m, tr.front(), pipe);
}

}  // namespace

double measure_value(const MeasureSpec& m, const RunOutcome& r, const PipeProgress* pipe) {
  switch (m.kind) {
    case MeasureSpec::Kind::Distance: return distance(m, r, pipe);
    case MeasureSpec::Kind::Speed: return r.sim_time_s > 0 ? distance(m, r, pipe) / r.sim_time_s : 0.0;
    case MeasureSpec::Kind::TimeToReach: {
      const auto& tr = track(m, r);
      for (size_t i = 0; i < tr.size(); ++i)
        if (along(m, tr[i], pipe) >= m.reach_m) return r.t_s[i];
      return m.never_s;
    }
    case MeasureSpec::Kind::Shortfall: {
      double furthest = -kInf;
      for (const auto& p : track(m, r)) furthest = std::max(furthest, along(m, p, pipe));
      return furthest >= m.reach_m ? 0.0 : m.reach_m - furthest;
    }
    case MeasureSpec::Kind::Energy: return r.energy_j;
    case MeasureSpec::Kind::EnergyPerM: {
      const double d = distance(m, r, pipe);
      return d > 0 ? r.energy_j / d : kInf;
    }
    case MeasureSpec::Kind::Modules: return r.modules;
  }
  return 0;
}

Score failed_score(size_t n_measures, const ObjectiveSpec& objective, const std::string& why) {
  Score s;
  s.measures.assign(n_measures, std::numeric_limits<double>::quiet_NaN());
  s.failed = true;
  s.why = why;
  s.fitness = objective.failed_fitness;
  return s;
}

Score score_run(const std::vector<MeasureSpec>& measures, const ObjectiveSpec& objective,
                const std::vector<ConstraintSpec>& constraints, const RunOutcome& run,
                const PipeProgress* pipe) {
  Score s;
  for (const auto& m : measures) s.measures.push_back(measure_value(m, run, pipe));
  auto fail = [&](const std::string& why) {
    s.failed = true;
    s.why = why;
    s.fitness = objective.failed_fitness;
    return s;
  };
  s.early_stop = run.early_stop;
  if (!run.finished) return fail(run.fault.empty() ? "the run did not finish" : run.fault);
  for (const auto& c : constraints) {
    const double v = s.measures[static_cast<size_t>(c.measure)];
    const std::string& name = measures[static_cast<size_t>(c.measure)].name;
    if (c.min && !(v >= *c.min)) return fail("constraint: " + name + " = " + general_text(v) + " < " + general_text(*c.min));
    if (c.max && !(v <= *c.max)) return fail("constraint: " + name + " = " + general_text(v) + " > " + general_text(*c.max));
  }
  double f = 0;
  for (const auto& [k, w] : objective.weights) f += w * s.measures[static_cast<size_t>(k)];
  if (!std::isfinite(f))
    return fail("the objective is not finite (" + general_text(f) + "): a measure used in it was never reached");
  s.fitness = f;
  return s;
}

}  // namespace chainsim

namespace chainsim {

Score combine_trials(const std::vector<Score>& trials, const ObjectiveSpec& objective, TrialFitness how, double q,
                     int asked) {
  const size_t n = trials.size();
  const size_t of = std::max(n, static_cast<size_t>(std::max(0, asked)));
  for (size_t r = 0; r < n; ++r)
    if (trials[r].failed) {
      Score s = trials[r];
      if (of > 1) s.why = "trial " + std::to_string(r + 1) + " of " + std::to_string(of) + ": " + s.why;
      s.trials = static_cast<int>(n);
      return s;
    }
  Score s;
  if (n == 1) {
    s = trials[0];
  } else {
    s.measures.assign(trials[0].measures.size(), 0.0);
    for (const auto& r : trials)
      for (size_t k = 0; k < s.measures.size(); ++k) s.measures[k] += r.measures[k] / static_cast<double>(n);
    for (const auto& [k, w] : objective.weights) s.fitness += w * s.measures[static_cast<size_t>(k)];
  }
  for (size_t r = 0; r < n; ++r)
    if (!trials[r].early_stop.empty()) {
      s.early_stop = n > 1 ? "trial " + std::to_string(r + 1) + " of " + std::to_string(n) + ": " + trials[r].early_stop
                           : trials[r].early_stop;
      break;
    }
  // the trials' fitnesses, worst first
  std::vector<double> f;
  for (const auto& r : trials) f.push_back(r.fitness);
  std::sort(f.begin(), f.end());
  if (objective.maximize == false) std::reverse(f.begin(), f.end());
  s.trials = static_cast<int>(n);
  s.fitness_min = *std::min_element(f.begin(), f.end());
  s.fitness_max = *std::max_element(f.begin(), f.end());
  if (n > 1) {
    double mean = 0, ss = 0;
    for (double v : f) mean += v / static_cast<double>(n);
    for (double v : f) ss += (v - mean) * (v - mean);
    s.fitness_sd = std::sqrt(ss / static_cast<double>(n - 1));
    if (how == TrialFitness::Worst) {
      s.fitness = f.front();
    } else if (how == TrialFitness::Quantile) {
      const double x = q * static_cast<double>(n - 1);
      const size_t i = static_cast<size_t>(std::floor(x));
      const double frac = x - static_cast<double>(i);
      s.fitness = i + 1 < n ? f[i] + frac * (f[i + 1] - f[i]) : f[i];
    }
  }
  return s;
}

}  // namespace chainsim
