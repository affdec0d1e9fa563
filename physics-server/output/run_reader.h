// The one reader of a finished run directory (docs/outputs.md), beside the
// writers: summary.json, trace.csv by column, bus.log's events and each
// endpoint's modules/NN-TYPE.log. `chainsim test`'s expectations, the design
// search's measures and the robot calibration's speeds all read runs through
// it. Files are read when first asked for, and kept.
//
// What it accepts of trace.csv: a header row; CRLF line ends; blank lines.
// A row with fewer or more cells than the header is the torn last row of a
// run that was stopped while writing when it is the file's last line, and
// is dropped; anywhere else it is an error naming the line. Every kept cell
// is a number as strtod reads it (nan and inf included); anything else is an
// error naming file:line:column and the column.
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

// a missing or unreadable file of the run directory, or one that does not
// parse; the message starts with the file's path (and line)
struct RunReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// reading given up because the stop check said so (chainsim test interrupted)
struct RunReadStopped : std::runtime_error {
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

struct RunReaderOptions {
  // asked every 4096 lines read; when it says true the read throws RunReadStopped
  std::function<bool()> stop;
  // the trace columns whose values are kept, by name (all when empty): a
  // reader that needs a few columns of a wide trace keeps only those
  std::function<bool(const std::string&)> keep_column;
};

class RunReader {
 public:
  explicit RunReader(std::string dir, RunReaderOptions options = {});
  // a run given as the files' text (tests, and text already read); `source`
  // stands for the directory in messages. A file given no text is missing.
  static RunReader from_text(std::string source, std::optional<std::string> summary_json,
                             std::optional<std::string> trace_csv, RunReaderOptions options = {});

  const std::string& dir() const { return dir_; }

  // summary.json; throws RunReadError when it is missing or not JSON
  const nlohmann::json& summary();
  double end_s();                               // the summary's sim_time_s (0 without one)
  int module_count();                           // modules of the chain (the central control not counted)
  int endpoint_index(bool central, int module); // central: the last endpoint

  // trace.csv: every column's name, in the file's order
  const std::vector<std::string>& trace_columns();
  // the values of a kept column; nullptr when the trace has no such column
  // or it was not kept
  const std::vector<double>* trace_column(const std::string& name);
  // column t_s; throws RunReadError when there is none
  const std::vector<double>& trace_time();
  // the bodies of module `module` in trace.csv, in the file's order: the
  // prefixes "mK.<body>" whose .x, .y and .z columns stand one after the
  // other (docs/outputs.md); empty when the trace has none for it. The
  // first is the module's first body (the head's, for module 0), the last
  // its last (the tail's, for the chain's last module)
  const std::vector<std::string>& body_columns(int module);
  // one more than the highest module with body columns (0: none)
  int body_column_modules();

  // bus.log's events
  const std::vector<BusEvent>& bus();
  // an endpoint's log lines (none when it logged nothing)
  const std::vector<LogLine>& log(int endpoint);

  // for loops over many items: asks the stop check at every 4096th i
  void poll_stop(size_t i) {
    if ((i & 4095) == 0 && options_.stop && options_.stop()) throw RunReadStopped("stopped while reading " + dir_);
  }

 private:
  void load_trace();
  std::string dir_;
  RunReaderOptions options_;
  bool from_text_ = false;
  std::optional<std::string> summary_text_, trace_text_;
  std::optional<nlohmann::json> summary_;
  bool trace_loaded_ = false;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> values_;  // by kept column
  std::map<std::string, size_t> kept_;        // column name -> index into values_
  std::optional<std::map<int, std::vector<std::string>>> bodies_;  // body_columns, by module
  std::optional<std::vector<BusEvent>> bus_;
  std::map<int, std::vector<LogLine>> logs_;
};

}  // namespace chainsim
