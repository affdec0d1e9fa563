#include "optimize/run_outcome.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace chainsim {

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunOutcomeError(path + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

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

}  // namespace

RunOutcome parse_run_outcome(const std::string& summary_json, const std::string& trace_csv,
                           const std::string& source) {
  RunOutcome r;
  nlohmann::json s;
  try {
    s = nlohmann::json::parse(summary_json);
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
    throw RunOutcomeError(source + "/summary.json: " + e.what());
  }

  std::istringstream in(trace_csv);
  std::string line;
  if (!std::getline(in, line)) throw RunOutcomeError(source + "/trace.csv: empty");
  const std::vector<std::string> cols = split(line, ',');
  const int hx = body_x_column(cols, 0, false);
  const int tx = body_x_column(cols, r.modules - 1, true);
  if (hx < 0 || tx < 0)
    throw RunOutcomeError(source + "/trace.csv: no body position columns for modules 0 and " +
                         std::to_string(r.modules - 1));
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    const std::vector<std::string> v = split(line, ',');
    if (v.size() != cols.size()) {
      // a run stopped by a fault may end in a torn row; anything else is damage
      if (in.peek() == EOF) break;
      throw RunOutcomeError(source + "/trace.csv:" + std::to_string(row) + ": " + std::to_string(v.size()) +
                           " fields, the header has " + std::to_string(cols.size()));
    }
    auto num = [&](int i) { return std::strtod(v[static_cast<size_t>(i)].c_str(), nullptr); };
    r.t_s.push_back(num(0));
    r.head.emplace_back(num(hx), num(hx + 1), num(hx + 2));
    r.tail.emplace_back(num(tx), num(tx + 1), num(tx + 2));
  }
  return r;
}

RunOutcome read_run_outcome(const std::string& run_dir) {
  return parse_run_outcome(slurp(run_dir + "/summary.json"), slurp(run_dir + "/trace.csv"), run_dir);
}

}  // namespace chainsim
