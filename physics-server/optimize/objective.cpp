#include "optimize/objective.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

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

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
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
  if (!run.finished) return fail(run.fault.empty() ? "the run did not finish" : run.fault);
  for (const auto& c : constraints) {
    const double v = s.measures[static_cast<size_t>(c.measure)];
    const std::string& name = measures[static_cast<size_t>(c.measure)].name;
    if (c.min && !(v >= *c.min)) return fail("constraint: " + name + " = " + num(v) + " < " + num(*c.min));
    if (c.max && !(v <= *c.max)) return fail("constraint: " + name + " = " + num(v) + " > " + num(*c.max));
  }
  double f = 0;
  for (const auto& [k, w] : objective.weights) f += w * s.measures[static_cast<size_t>(k)];
  if (!std::isfinite(f))
    return fail("the objective is not finite (" + num(f) + "): a measure used in it was never reached");
  s.fitness = f;
  return s;
}

}  // namespace chainsim

namespace chainsim {

Score combine_repeats(const std::vector<Score>& repeats, const ObjectiveSpec& objective) {
  if (repeats.size() == 1) return repeats[0];
  for (size_t r = 0; r < repeats.size(); ++r)
    if (repeats[r].failed) {
      Score s = repeats[r];
      s.why = "repeat " + std::to_string(r + 1) + " of " + std::to_string(repeats.size()) + ": " + s.why;
      return s;
    }
  Score s;
  s.measures.assign(repeats[0].measures.size(), 0.0);
  for (const auto& r : repeats)
    for (size_t k = 0; k < s.measures.size(); ++k) s.measures[k] += r.measures[k] / static_cast<double>(repeats.size());
  for (const auto& [k, w] : objective.weights) s.fitness += w * s.measures[static_cast<size_t>(k)];
  return s;
}

}  // namespace chainsim
