// The run directory's files. See run_output.h.
#include "output/run_output.h"

#include <cerrno>
#include <cinttypes>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "output/decimal.h"

namespace chainsim {

namespace {
FILE* open_or_throw(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "we");  // close-on-exec: module processes must not inherit it
  if (!f) throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
  std::setvbuf(f, nullptr, _IOFBF, 1 << 16);
  return f;
}
}  // namespace

RunOutput::RunOutput(const std::string& dir, const std::vector<std::string>& endpoint_names)
    : dir_(dir), names_(endpoint_names), logs_(endpoint_names.size(), nullptr) {
  std::error_code ec;
  std::filesystem::create_directories(dir_ + "/modules", ec);
  if (ec) throw std::runtime_error("cannot create run directory " + dir_ + ": " + ec.message());
  trace_ = open_or_throw(path("trace.csv"));
  bus_ = open_or_throw(path("bus.log"));
}

RunOutput::~RunOutput() {
  flush();
  if (trace_) std::fclose(trace_);
  if (bus_) std::fclose(bus_);
  for (FILE* f : logs_)
    if (f) std::fclose(f);
}

std::string RunOutput::module_file(int endpoint, const char* suffix) const {
  char name[64];
  std::snprintf(name, sizeof name, "modules/%02d-%s.%s", endpoint, names_[endpoint].c_str(), suffix);
  return path(name);
}

void RunOutput::trace(const std::string& bytes) {
  std::fwrite(bytes.data(), 1, bytes.size(), trace_);
  sha_.update(bytes.data(), bytes.size());
  trace_bytes_ += bytes.size();
}

void RunOutput::bus(int64_t t_us, const char* line) {
  std::fprintf(bus_, "%" PRId64 " %s\n", t_us, line);
}

void RunOutput::module_log(int endpoint, int64_t t_us, const char* line) {
  FILE*& f = logs_[endpoint];
  if (!f) f = open_or_throw(module_file(endpoint, "log"));
  const std::string t = seconds_text(t_us);
  std::fprintf(f, "%s %s\n", t.c_str(), line);
}

void RunOutput::flush() {
  if (trace_) std::fflush(trace_);
  if (bus_) std::fflush(bus_);
  for (FILE* f : logs_)
    if (f) std::fflush(f);
}

std::string RunOutput::trace_sha256() {
  if (sha_hex_.empty()) sha_hex_ = sha_.hex();
  return sha_hex_;
}

void RunOutput::write_json(const std::string& name, const nlohmann::json& value) {
  const std::string tmp = path(name + ".tmp");
  {
    std::ofstream out(tmp);
    out << value.dump(2) << "\n";
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path(name), ec);
  if (ec) throw std::runtime_error("cannot write " + path(name) + ": " + ec.message());
}

}  // namespace chainsim
