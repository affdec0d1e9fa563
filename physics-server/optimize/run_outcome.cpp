#include "optimize/run_outcome.h"

#include <nlohmann/json.hpp>

#include "output/run_reader.h"

namespace chainsim {

namespace {

// index of "m<k>.<body>.x" for the first (or last) body of module k
int body_x_column(const std::vector<std::string>& cols, int k, bool last) {
  const std::string pre = "m" + std::to_string(k) + ".";
  int found = -1;
  for (size_t i = 0; i < cols.size(); ++i) {
    const std::string& c = cols[i];
    if (c.rfind(pre, 0) == 0 && c.size() > 2 && c.compare(c.size() - 2, 2, ".x") == 0 &&
        i + 2 < cols.size() && cols[i + 1] == c.substr(0, c.size() - 1) + "y") {
      found = static_cast<int>(i);
      if (!last) break;
    }
  }
  return found;
}


// the outcome from the run's files (the trace read with outcome_column)
RunOutcome outcome_of(RunReader& run) {
  RunOutcome r;
  const std::string summary_file = run.dir() + "/summary.json";
  try {
    const nlohmann::json& s = run.summary();
    r.sim_time_s = s.at("sim_time_s").get<double>();
    std::string module_fault;  // with --on-module-fault=limp a run can finish with one
    for (const auto& m : s.at("modules")) {
      if (m.contains("energy_j")) {
        r.energy_j += m["energy_j"].get<double>();
        ++r.modules;
      }
      if (!m.at("fault").is_null() && module_fault.empty()) module_fault = m["fault"].get<std::string>();
    }
    const auto& d = s.at("chain").at("displacement_m");
    r.chain_displacement = {d.at(0).get<double>(), d.at(1).get<double>(), d.at(2).get<double>()};
    const int code = s.at("exit_code").get<int>();
    if (code != 0)
      r.fault = !s.at("stopped_by").is_null() ? s["stopped_by"].get<std::string>()
                : !module_fault.empty()       ? module_fault
                                              : "exit code " + std::to_string(code);
    else
      r.fault = module_fault;
    r.finished = r.fault.empty();
    if (s.contains("early_stop") && s["early_stop"].is_string()) r.early_stop = s["early_stop"].get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw RunReadError(summary_file + ": " + e.what());
  }

  const std::vector<std::string>& cols = run.trace_columns();
  const int hx = body_x_column(cols, 0, false);
  const int tx = body_x_column(cols, r.modules - 1, true);
  if (hx < 0 || tx < 0)
    throw RunReadError(run.dir() + "/trace.csv: no body position columns for modules 0 and " +
                       std::to_string(r.modules - 1));
  const auto track = [&](int x) {
    const std::vector<double>* c[3];
    for (int i = 0; i < 3; ++i) c[i] = run.trace_column(cols[static_cast<size_t>(x + i)]);
    std::vector<Eigen::Vector3d> out;
    out.reserve(c[0]->size());
    for (size_t k = 0; k < c[0]->size(); ++k) out.emplace_back((*c[0])[k], (*c[1])[k], (*c[2])[k]);
    return out;
  };
  r.t_s = run.trace_time();
  r.head = track(hx);
  r.tail = track(tx);
  return r;
}

// the columns outcome_of reads: time and body positions
bool outcome_column(const std::string& name) {
  if (name == "t_s") return true;
  const size_t n = name.size();
  return name.rfind("m", 0) == 0 && n > 2 && name[n - 2] == '.' &&
         (name[n - 1] == 'x' || name[n - 1] == 'y' || name[n - 1] == 'z');
}

}  // namespace

RunOutcome parse_run_outcome(const std::string& summary_json, const std::string& trace_csv,
                             const std::string& source) {
  RunReader run = RunReader::from_text(source, summary_json, trace_csv, {{}, outcome_column});
  return outcome_of(run);
}

RunOutcome read_run_outcome(const std::string& run_dir) {
  RunReader run(run_dir, {{}, outcome_column});
  return outcome_of(run);
}

}  // namespace chainsim
