// The run directory's files. See run_output.h.
#include "output/run_output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "text/number_text.h"

namespace chainsim {

namespace {
constexpr size_t kTraceBufferBytes = 1 << 16;

FILE* open_or_throw(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "we");  // close-on-exec: module processes must not inherit it
  if (!f) throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
  std::setvbuf(f, nullptr, _IOFBF, 1 << 16);
  return f;
}
// cut the file of fd back to just after its last newline: a row torn by a
// failed write goes, the whole rows before it stay
void cut_to_last_newline(int fd) {
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return;
  char buf[4096];
  off_t end = st.st_size;
  while (end > 0) {
    const off_t from = std::max<off_t>(0, end - static_cast<off_t>(sizeof buf));
    const ssize_t n = pread(fd, buf, static_cast<size_t>(end - from), from);
    if (n <= 0) return;
    for (ssize_t i = n - 1; i >= 0; --i)
      if (buf[i] == '\n') {
        if (ftruncate(fd, from + i + 1) != 0) return;
        return;
      }
    end = from;
  }
  if (ftruncate(fd, 0) != 0) return;
}

}  // namespace

RunOutput::RunOutput(const std::string& dir, const std::vector<std::string>& endpoint_names)
    : dir_(dir), names_(endpoint_names), logs_(endpoint_names.size(), nullptr) {
  std::error_code ec;
  std::filesystem::create_directories(dir_ + "/modules", ec);
  if (ec) throw std::runtime_error("cannot create run directory " + dir_ + ": " + ec.message());
  trace_ = open_or_throw(path("trace.csv"));
  // buffered here, in whole rows (stdio would write out a full buffer mid-row)
  std::setvbuf(trace_, nullptr, _IONBF, 0);
  trace_buffer_.reserve(kTraceBufferBytes);
  bus_ = open_or_throw(path("bus.log"));
  events_ = open_or_throw(path("events.jsonl"));
  // every endpoint's log exists from the start, empty until it logs (a
  // missing file would look like a lost one); opened again at the first line.
  // Its process's output (.out, which the process appends to) starts empty
  // too, and no PIC figures (.pic.json) of an earlier run in this directory stay.
  for (size_t i = 0; i < names_.size(); ++i) {
    std::fclose(open_or_throw(module_file(static_cast<int>(i), "log")));
    std::fclose(open_or_throw(module_file(static_cast<int>(i), "out")));
    std::filesystem::remove(module_file(static_cast<int>(i), "pic.json"), ec);
  }
}

RunOutput::~RunOutput() {
  flush();
  if (trace_) std::fclose(trace_);
  if (bus_) std::fclose(bus_);
  if (events_) std::fclose(events_);
  for (FILE* f : logs_)
    if (f) std::fclose(f);
}

std::string RunOutput::module_file(int endpoint, const char* suffix) const {
  char name[64];
  std::snprintf(name, sizeof name, "modules/%02d-%s.%s", endpoint, names_[endpoint].c_str(), suffix);
  return path(name);
}

void RunOutput::failed(FILE* f, const std::string& file) {
  const int err = errno;
  if (write_error_.empty()) write_error_ = "cannot write " + file + ": " + std::strerror(err);
  if (f == trace_) {
    // stdio may have written part of its buffer: no more writes, then whole rows only
    std::fclose(trace_);
    trace_ = nullptr;
    struct stat st;
    if (stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;  // e.g. /dev/full: nothing kept to cut
    const int fd = open(file.c_str(), O_RDWR | O_CLOEXEC);
    if (fd >= 0) {
      cut_to_last_newline(fd);
      close(fd);
    }
    // the hash and size then describe the file as it stays
    Sha256 kept;
    trace_bytes_ = 0;
    std::ifstream in(file, std::ios::binary);
    char buf[1 << 16];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
      kept.update(buf, static_cast<size_t>(in.gcount()));
      trace_bytes_ += static_cast<size_t>(in.gcount());
    }
    sha_hex_ = kept.hex();
  }
}

void RunOutput::trace(const std::string& bytes) {
  if (!trace_) return;  // a write failed: the file keeps its whole rows, nothing after
  // the buffer goes out before a row would overflow it, so the file only ever
  // receives whole rows: a server killed outright leaves no torn one
  if (trace_buffer_.size() + bytes.size() > kTraceBufferBytes && !write_trace_buffer()) return;
  trace_buffer_ += bytes;
  sha_.update(bytes.data(), bytes.size());
  trace_bytes_ += bytes.size();
}

bool RunOutput::write_trace_buffer() {
  if (!trace_ || trace_buffer_.empty()) return trace_ != nullptr;
  // unbuffered: one write of whole rows (a failed one is cut back to them)
  if (std::fwrite(trace_buffer_.data(), 1, trace_buffer_.size(), trace_) != trace_buffer_.size()) {
    failed(trace_, path("trace.csv"));
    return false;
  }
  trace_buffer_.clear();
  return true;
}

void RunOutput::bus(int64_t t_us, const char* line) {
  if (bus_ && std::fprintf(bus_, "%" PRId64 " %s\n", t_us, line) < 0) failed(bus_, path("bus.log"));
}

void RunOutput::event(const std::string& line) {
  if (events_ && std::fprintf(events_, "%s\n", line.c_str()) < 0) failed(events_, path("events.jsonl"));
}

void RunOutput::module_log(int endpoint, int64_t t_us, const char* line) {
  FILE*& f = logs_[endpoint];
  if (!f) {
    f = std::fopen(module_file(endpoint, "log").c_str(), "ae");  // created empty at the start
    if (!f) return failed(nullptr, module_file(endpoint, "log"));
  }
  const std::string t = seconds_text(t_us);
  if (std::fprintf(f, "%s %s\n", t.c_str(), line) < 0) failed(f, module_file(endpoint, "log"));
}

void RunOutput::flush() {
  write_trace_buffer();
  if (bus_ && std::fflush(bus_) != 0) failed(bus_, path("bus.log"));
  if (events_ && std::fflush(events_) != 0) failed(events_, path("events.jsonl"));
  for (size_t i = 0; i < logs_.size(); ++i)
    if (logs_[i] && std::fflush(logs_[i]) != 0) failed(logs_[i], module_file(static_cast<int>(i), "log"));
}

std::string RunOutput::trace_sha256() {
  if (sha_hex_.empty()) sha_hex_ = sha_.hex();
  return sha_hex_;
}

void RunOutput::write_json(const std::string& name, const nlohmann::json& value) {
  const std::string tmp = path(name + ".tmp");
  std::error_code ec_rm;
  {
    std::ofstream out(tmp);
    out << value.dump(2) << "\n";
    out.flush();
    if (!out) {
      const int err = errno;
      if (std::filesystem::is_regular_file(tmp, ec_rm)) std::filesystem::remove(tmp, ec_rm);
      throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(err));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path(name), ec);
  if (ec) {
    std::filesystem::remove(tmp, ec_rm);
    throw std::runtime_error("cannot write " + path(name) + ": " + ec.message());
  }
}

}  // namespace chainsim
