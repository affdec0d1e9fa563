// The files of a run directory: trace.csv, bus.log, events.jsonl, modules/<i>-<type>.log
// (and the .out files the processes write themselves), scene.json and
// summary.json. Written as the run goes, flushed often, so a run that ends by
// a fault or Ctrl-C keeps everything produced until then. A write that fails
// (a full disk, an I/O error) is kept as write_error() for the run loop to
// stop on at once; the trace is then cut back to its last whole row. The
// trace reaches its file in whole rows only, so even a server killed outright
// leaves none torn.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "output/sha256.h"

namespace chainsim {

class RunOutput {
 public:
  // creates dir (and dir/modules) if missing, trace.csv, bus.log, events.jsonl and every
  // endpoint's (empty) log; throws
  // std::runtime_error naming the path. endpoint_names[i]: endpoint i's type
  RunOutput(const std::string& dir, const std::vector<std::string>& endpoint_names);
  ~RunOutput();
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  const std::string& dir() const { return dir_; }

  void trace(const std::string& bytes);        // appended and hashed
  void bus(int64_t t_us, const char* line);    // one bus-log line: "<t_us> <line>"
  void event(const std::string& line);         // one line of events.jsonl (run_events.h)
  // one line of endpoint's log, "<t_s> <line>"
  void module_log(int endpoint, int64_t t_us, const char* line);
  void flush();

  // the first write that failed, "cannot write DIR/trace.csv: No space left on
  // device"; empty while every write succeeded
  const std::string& write_error() const { return write_error_; }

  // finishes the trace hash; call once at the end (later calls return the same)
  std::string trace_sha256();
  size_t trace_bytes() const { return trace_bytes_; }

  // write dir/name atomically (temp file + rename): readers see the old file
  // or the whole new one. Throws std::runtime_error naming the file (and
  // removes the temp file).
  void write_json(const std::string& name, const nlohmann::json& value);
  void write_summary(const nlohmann::json& summary) { write_json("summary.json", summary); }

  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  // dir/modules/<NN>-<type>.<suffix>
  std::string module_file(int endpoint, const char* suffix) const;

 private:
  std::string dir_;
  std::vector<std::string> names_;
  FILE* trace_ = nullptr;
  FILE* bus_ = nullptr;
  FILE* events_ = nullptr;
  std::vector<FILE*> logs_;
  Sha256 sha_;
  size_t trace_bytes_ = 0;
  std::string trace_buffer_;  // whole rows not yet written to trace_
  std::string sha_hex_;
  std::string write_error_;

  // after a failed write or flush of f (at path): keep the first error; the
  // trace is cut back to its last whole row
  void failed(FILE* f, const std::string& path);
  // trace_buffer_ to the file; false (and failed()) when the write failed
  bool write_trace_buffer();
};

}  // namespace chainsim
