// The files of a run directory: trace.csv, bus.log, modules/<i>-<type>.log
// (and the .out files the processes write themselves), scene.json and
// summary.json. Written as the run goes, flushed often, so a run that ends by
// a fault or Ctrl-C keeps everything produced until then.
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
  // creates dir (and dir/modules) if missing, trace.csv and bus.log; throws
  // std::runtime_error naming the path. endpoint_names[i]: endpoint i's type
  RunOutput(const std::string& dir, const std::vector<std::string>& endpoint_names);
  ~RunOutput();
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  const std::string& dir() const { return dir_; }

  void trace(const std::string& bytes);        // appended and hashed
  void bus(int64_t t_us, const char* line);    // one bus-log line: "<t_us> <line>"
  // one line of endpoint's log, "<t_s> <line>" (the file is created at its first line)
  void module_log(int endpoint, int64_t t_us, const char* line);
  void flush();

  // finishes the trace hash; call once at the end (later calls return the same)
  std::string trace_sha256();
  size_t trace_bytes() const { return trace_bytes_; }

  // write dir/name atomically (temp file + rename): readers see the old file
  // or the whole new one. Throws std::runtime_error naming the file.
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
  std::vector<FILE*> logs_;
  Sha256 sha_;
  size_t trace_bytes_ = 0;
  std::string sha_hex_;
};

}  // namespace chainsim
