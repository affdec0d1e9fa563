// The one reader of a run directory (run_reader.h).
#include "output/run_reader.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "readers/safe_text.h"

namespace chainsim {
namespace {

std::unique_ptr<std::istream> open_run_file(const std::string& path) {
  auto f = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*f) throw RunReadError(path + ": cannot open");
  return f;
}

// the line without its CR of a CRLF end
void chop_cr(std::string& line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
}

// [begin, end) of each comma-separated cell of line, into *out (reused from
// row to row: no allocation per row once it has grown)
void cell_spans(const std::string& line, std::vector<std::pair<size_t, size_t>>* out) {
  out->clear();
  size_t b = 0;
  for (;;) {
    const size_t e = line.find(',', b);
    out->emplace_back(b, e == std::string::npos ? line.size() : e);
    if (e == std::string::npos) return;
    b = e + 1;
  }
}

}  // namespace

RunReader::RunReader(std::string dir, RunReaderOptions options) : dir_(std::move(dir)), options_(std::move(options)) {}

RunReader RunReader::from_text(std::string source, std::optional<std::string> summary_json,
                               std::optional<std::string> trace_csv, RunReaderOptions options) {
  RunReader r(std::move(source), std::move(options));
  r.from_text_ = true;
  r.summary_text_ = std::move(summary_json);
  r.trace_text_ = std::move(trace_csv);
  return r;
}

const nlohmann::json& RunReader::summary() {
  if (summary_) return *summary_;
  const std::string p = dir_ + "/summary.json";
  try {
    if (from_text_) {
      if (!summary_text_) throw RunReadError(p + ": cannot open");
      summary_ = nlohmann::json::parse(*summary_text_);
    } else {
      summary_ = nlohmann::json::parse(*open_run_file(p));
    }
  } catch (const nlohmann::json::exception& e) {
    throw RunReadError(p + ": " + e.what());
  }
  return *summary_;
}

double RunReader::end_s() {
  const auto& s = summary();
  return s.contains("sim_time_s") && s["sim_time_s"].is_number() ? s["sim_time_s"].get<double>() : 0.0;
}

int RunReader::module_count() {
  int n = 0;
  for (const auto& m : summary().value("modules", nlohmann::json::array()))
    if (m.value("type", std::string()) != "central") ++n;
  return n;
}

int RunReader::endpoint_index(bool central, int module) { return central ? module_count() : module; }

void RunReader::load_trace() {
  if (trace_loaded_) return;
  const std::string p = dir_ + "/trace.csv";
  std::unique_ptr<std::istream> in;
  if (from_text_) {
    if (!trace_text_) throw RunReadError(p + ": cannot open");
    in = std::make_unique<std::istringstream>(*trace_text_);
  } else {
    in = open_run_file(p);
  }
  std::string line;
  if (!std::getline(*in, line)) throw RunReadError(p + ": empty (no header)");
  chop_cr(line);
  std::vector<int> slot;  // per column: its index into values_, or -1 when not kept
  std::vector<std::pair<size_t, size_t>> spans;
  cell_spans(line, &spans);
  for (const auto& [b, e] : spans) {
    columns_.push_back(line.substr(b, e - b));
    const std::string& name = columns_.back();
    if (!options_.keep_column || options_.keep_column(name)) {
      slot.push_back(static_cast<int>(values_.size()));
      kept_[name] = values_.size();
      values_.emplace_back();
    } else {
      slot.push_back(-1);
    }
  }
  int line_no = 1;
  for (size_t n = 0; std::getline(*in, line); ++n) {
    ++line_no;
    poll_stop(n);
    chop_cr(line);
    if (line.empty()) continue;
    cell_spans(line, &spans);
    if (spans.size() != columns_.size()) {
      // a run stopped while writing leaves its last row torn; anything else is damage
      if (in->peek() == std::char_traits<char>::eof()) break;
      throw RunReadError(p + ":" + std::to_string(line_no) + ": " + std::to_string(spans.size()) +
                         " cells, the header has " + std::to_string(columns_.size()));
    }
    for (size_t i = 0; i < spans.size(); ++i) {
      if (slot[i] < 0) continue;
      const auto [b, e] = spans[i];
      const char* start = line.c_str() + b;
      char* end = nullptr;
      const double v = std::strtod(start, &end);
      if (e == b || end != line.c_str() + e)
        throw RunReadError(p + ":" + std::to_string(line_no) + ":" + std::to_string(b + 1) + ": '" +
                           shown_text_cut(line.substr(b, e - b), 80) + "' in column '" + shown_text_cut(columns_[i], 80) +
                           "' is not a number");
      values_[static_cast<size_t>(slot[i])].push_back(v);
    }
  }
  trace_loaded_ = true;
}

const std::vector<std::string>& RunReader::trace_columns() {
  load_trace();
  return columns_;
}

const std::vector<double>* RunReader::trace_column(const std::string& name) {
  load_trace();
  const auto it = kept_.find(name);
  return it == kept_.end() ? nullptr : &values_[it->second];
}

const std::vector<double>& RunReader::trace_time() {
  const auto* t = trace_column("t_s");
  if (!t) throw RunReadError(dir_ + "/trace.csv: no t_s column");
  return *t;
}

const std::vector<std::string>& RunReader::body_columns(int module) {
  if (!bodies_) {
    // one place that knows how a body's position is named in the trace;
    // a sensor's or wheel's columns (x_counts, n_N, ...) never end in .x, .y, .z
    const std::vector<std::string>& c = trace_columns();
    bodies_.emplace();
    for (size_t i = 0; i + 2 < c.size(); ++i) {
      const std::string& x = c[i];
      size_t d = 1;
      while (d < x.size() && x[d] >= '0' && x[d] <= '9') ++d;
      if (x.size() < 2 || x[0] != 'm' || d == 1 || d > 9 || d + 3 >= x.size() || x[d] != '.' || !x.ends_with(".x"))
        continue;
      const std::string body = x.substr(0, x.size() - 2);
      if (c[i + 1] != body + ".y" || c[i + 2] != body + ".z") continue;
      (*bodies_)[std::stoi(x.substr(1, d - 1))].push_back(body);
    }
  }
  static const std::vector<std::string> kNone;
  const auto it = bodies_->find(module);
  return it == bodies_->end() ? kNone : it->second;
}

int RunReader::body_column_modules() {
  body_columns(0);
  return bodies_->empty() ? 0 : bodies_->rbegin()->first + 1;
}

const std::vector<BusEvent>& RunReader::bus() {
  if (bus_) return *bus_;
  const std::string p = dir_ + "/bus.log";
  if (from_text_) throw RunReadError(p + ": cannot open");
  auto f = open_run_file(p);
  bus_.emplace();
  std::string line;
  for (size_t n = 0; std::getline(*f, line); ++n) {
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

const std::vector<LogLine>& RunReader::log(int endpoint) {
  auto it = logs_.find(endpoint);
  if (it != logs_.end()) return it->second;
  std::vector<LogLine>& out = logs_[endpoint];
  if (from_text_) return out;
  char prefix[16];
  std::snprintf(prefix, sizeof prefix, "%02d-", endpoint);
  std::error_code ec;
  // sorted, so that two logs of one endpoint (never written by a run) come in one order
  std::vector<std::filesystem::path> files;
  for (const auto& de : std::filesystem::directory_iterator(dir_ + "/modules", ec)) {
    const std::string name = de.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && de.path().extension() == ".log") files.push_back(de.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& path : files) {
    auto f = open_run_file(path.string());
    std::string line;
    for (size_t n = 0; std::getline(*f, line); ++n) {
      poll_stop(n);
      const size_t sp = line.find(' ');
      if (sp == std::string::npos) continue;
      out.push_back({std::atof(line.substr(0, sp).c_str()), line.substr(sp + 1)});
    }
  }
  return out;
}

}  // namespace chainsim
