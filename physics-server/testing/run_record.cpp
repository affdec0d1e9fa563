#include "testing/run_record.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace chainsim {
namespace {

std::ifstream open_input(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw RunRecordError("cannot read " + path);
  return f;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  size_t b = 0;
  for (;;) {
    const size_t e = line.find(sep, b);
    out.push_back(line.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) return out;
    b = e + 1;
  }
}

}  // namespace

const nlohmann::json& RunRecord::summary() {
  if (!summary_) {
    const std::string p = dir_ + "/summary.json";
    std::ifstream f = open_input(p);
    try {
      summary_ = nlohmann::json::parse(f);
    } catch (const nlohmann::json::exception& e) {
      throw RunRecordError(p + ": " + e.what());
    }
  }
  return *summary_;
}

double RunRecord::end_s() {
  const auto& s = summary();
  return s.contains("sim_time_s") && s["sim_time_s"].is_number() ? s["sim_time_s"].get<double>() : 0.0;
}

int RunRecord::module_count() {
  int n = 0;
  for (const auto& m : summary().value("modules", nlohmann::json::array()))
    if (m.value("type", std::string()) != "central") ++n;
  return n;
}

int RunRecord::endpoint_index(bool central, int module) { return central ? module_count() : module; }

void RunRecord::load_trace() {
  if (trace_loaded_) return;
  const std::string p = dir_ + "/trace.csv";
  std::ifstream f = open_input(p);
  std::string line;
  if (!std::getline(f, line)) throw RunRecordError(p + ": empty (no header)");
  columns_ = split(line, ',');
  values_.assign(columns_.size(), {});
  for (size_t i = 0; i < columns_.size(); ++i) column_index_[columns_[i]] = i;
  for (size_t n = 0; std::getline(f, line); ++n) {
    poll_stop(n);
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line, ',');
    if (cells.size() != columns_.size()) break;  // a row cut short by a stopped run
    for (size_t i = 0; i < cells.size(); ++i) {
      char* e = nullptr;
      const double v = std::strtod(cells[i].c_str(), &e);
      values_[i].push_back(e == cells[i].c_str() ? std::nan("") : v);
    }
  }
  trace_loaded_ = true;
}

const std::vector<std::string>& RunRecord::trace_columns() {
  load_trace();
  return columns_;
}

const std::vector<double>& RunRecord::trace_time() {
  const auto* t = trace_column("t_s");
  if (!t) throw RunRecordError(dir_ + "/trace.csv: no t_s column");
  return *t;
}

const std::vector<double>* RunRecord::trace_column(const std::string& name) {
  load_trace();
  const auto it = column_index_.find(name);
  return it == column_index_.end() ? nullptr : &values_[it->second];
}

const std::vector<BusEvent>& RunRecord::bus() {
  if (bus_) return *bus_;
  std::ifstream f = open_input(dir_ + "/bus.log");
  bus_.emplace();
  std::string line;
  for (size_t n = 0; std::getline(f, line); ++n) {
    poll_stop(n);
    std::istringstream s(line);
    BusEvent ev;
    if (!(s >> ev.t_us >> ev.event)) continue;
    std::getline(s, ev.text);
    if (!ev.text.empty() && ev.text[0] == ' ') ev.text.erase(0, 1);
    if (ev.event != "fault") {
      std::istringstream kv(ev.text);
      std::string w;
      while (kv >> w) {
        const size_t eq = w.find('=');
        if (eq != std::string::npos) ev.field[w.substr(0, eq)] = w.substr(eq + 1);
      }
    }
    bus_->push_back(std::move(ev));
  }
  return *bus_;
}

const std::vector<LogLine>& RunRecord::log(int endpoint) {
  auto it = logs_.find(endpoint);
  if (it != logs_.end()) return it->second;
  std::vector<LogLine>& out = logs_[endpoint];
  char prefix[16];
  std::snprintf(prefix, sizeof prefix, "%02d-", endpoint);
  std::error_code ec;
  for (const auto& de : std::filesystem::directory_iterator(dir_ + "/modules", ec)) {
    const std::string name = de.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || de.path().extension() != ".log") continue;
    std::ifstream f = open_input(de.path().string());
    std::string line;
    for (size_t n = 0; std::getline(f, line); ++n) {
      poll_stop(n);
      const size_t sp = line.find(' ');
      if (sp == std::string::npos) continue;
      out.push_back({std::atof(line.substr(0, sp).c_str()), line.substr(sp + 1)});
    }
  }
  return out;
}

}  // namespace chainsim
