// What a finished run directory holds, read back for the expectations:
// summary.json, trace.csv (by column), bus.log (parsed events) and each
// endpoint's modules/NN-TYPE.log. Files are read when first asked for.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace chainsim {

// a missing or unreadable file of the run directory, or one that does not parse
struct RunRecordError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// reading or measuring given up because the stop check said so (chainsim
// test interrupted)
struct RunRecordStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// one bus.log line: "<t_us> <event> key=value ...", or "<t_us> fault <text>"
struct BusEvent {
  int64_t t_us = 0;
  std::string event;                         // i2c, i2c-drop, sync, addr, touch, fault
  std::map<std::string, std::string> field;  // from, to, data, endpoint, sout, address, level
  std::string text;                          // the rest of the line
};

// one modules/NN-TYPE.log line: "<seconds> <text>"
struct LogLine {
  double t_s = 0;
  std::string text;
};

class RunRecord {
 public:
  explicit RunRecord(std::string dir) : dir_(std::move(dir)) {}
  // stop is asked every few thousand lines read or measured; when it says
  // true, the read or the measurement throws RunRecordStopped
  RunRecord(std::string dir, std::function<bool()> stop) : dir_(std::move(dir)), stop_(std::move(stop)) {}

  const std::string& dir() const { return dir_; }
  const nlohmann::json& summary();              // throws when summary.json is missing
  double end_s();                               // the summary's sim_time_s
  int module_count();                           // modules of the chain (the central control not counted)
  int endpoint_index(bool central, int module); // central: the last endpoint

  // trace.csv
  const std::vector<std::string>& trace_columns();
  const std::vector<double>& trace_time();      // column t_s
  // a column's values; nullptr when the trace has no such column
  const std::vector<double>* trace_column(const std::string& name);

  const std::vector<BusEvent>& bus();
  // an endpoint's log lines (none when it logged nothing)
  const std::vector<LogLine>& log(int endpoint);

  // for loops over lines: asks the stop check at every 4096th i
  void poll_stop(size_t i) {
    if ((i & 4095) == 0 && stop_ && stop_()) throw RunRecordStopped("stopped while reading " + dir_);
  }

 private:
  void load_trace();
  std::string dir_;
  std::function<bool()> stop_;
  std::optional<nlohmann::json> summary_;
  bool trace_loaded_ = false;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> values_;  // by column
  std::map<std::string, size_t> column_index_;
  std::optional<std::vector<BusEvent>> bus_;
  std::map<int, std::vector<LogLine>> logs_;
};

}  // namespace chainsim
