// The files of a run directory: trace.csv, bus.log, modules/<i>-<type>.log and
// summary.json. Written as the run goes, flushed often, so a run that ends by
// a fault or Ctrl-C keeps everything produced until then.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace chainsim {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(const void* data, size_t len);
  std::string hex();  // finishes; call once
 private:
  void* ctx_;
};

class RunOutput {
 public:
  // creates dir (and dir/modules) if missing; throws std::runtime_error naming the path
  RunOutput(const std::string& dir, const std::vector<std::string>& endpoint_names);
  ~RunOutput();
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  const std::string& dir() const { return dir_; }

  void trace(const std::string& bytes);        // appended and hashed
  void bus(int64_t t_us, const char* line);    // one bus-log line
  void module_log(int endpoint, int64_t t_us, const char* line);
  void flush();

  // finishes the trace hash; call once at the end
  std::string trace_sha256();
  size_t trace_bytes() const { return trace_bytes_; }

  // write summary.json atomically (temp file + rename)
  void write_summary(const nlohmann::json& summary);

  std::string path(const std::string& name) const { return dir_ + "/" + name; }
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
