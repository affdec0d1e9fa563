#include "optimize/run_outcome.h"

#include <nlohmann/json.hpp>

#include "output/run_reader.h"

namespace chainsim {

namespace {

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

  // the head's first body and the tail's last
  const std::vector<std::string>& head = run.body_columns(0);
  const std::vector<std::string>& tail = run.body_columns(r.modules - 1);
  if (head.empty() || tail.empty())
    throw RunReadError(run.dir() + "/trace.csv: no body position columns for modules 0 and " +
                       std::to_string(r.modules - 1));
  const auto track = [&](const std::string& body) {
    const std::vector<double>* c[3] = {run.trace_column(body + ".x"), run.trace_column(body + ".y"),
                                       run.trace_column(body + ".z")};
    std::vector<Eigen::Vector3d> out;
    out.reserve(c[0]->size());
    for (size_t k = 0; k < c[0]->size(); ++k) out.emplace_back((*c[0])[k], (*c[1])[k], (*c[2])[k]);
    return out;
  };
  r.t_s = run.trace_time();
  r.head = track(head.front());
  r.tail = track(tail.back());
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
