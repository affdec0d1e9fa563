#include "output/run_output.h"

#include <openssl/evp.h>
#include <sys/stat.h>

#include <cerrno>
#include <cinttypes>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace chainsim {

Sha256::Sha256() : ctx_(EVP_MD_CTX_new()) {
  EVP_DigestInit_ex(static_cast<EVP_MD_CTX*>(ctx_), EVP_sha256(), nullptr);
}
Sha256::~Sha256() { EVP_MD_CTX_free(static_cast<EVP_MD_CTX*>(ctx_)); }
void Sha256::update(const void* data, size_t len) {
  EVP_DigestUpdate(static_cast<EVP_MD_CTX*>(ctx_), data, len);
}
std::string Sha256::hex() {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_DigestFinal_ex(static_cast<EVP_MD_CTX*>(ctx_), md, &n);
  static const char* digits = "0123456789abcdef";
  std::string s;
  for (unsigned i = 0; i < n; ++i) {
    s += digits[md[i] >> 4];
    s += digits[md[i] & 15];
  }
  return s;
}

namespace {
FILE* open_or_throw(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "w");
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
  std::fprintf(f, "%" PRId64 ".%06" PRId64 " %s\n", t_us / 1000000, t_us % 1000000, line);
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

void RunOutput::write_summary(const nlohmann::json& summary) {
  const std::string tmp = path("summary.json.tmp");
  {
    std::ofstream out(tmp);
    out << summary.dump(2) << "\n";
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path("summary.json"));
}

}  // namespace chainsim
