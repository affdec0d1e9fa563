// The run directory checked before a run. See run_dir.h.
#include "output/run_dir.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace chainsim {

RunDirCheck prepare_run_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  RunDirCheck r;
  const std::string name = "--out '" + dir + "'";
  if (dir.empty()) {
    r.error = "--out: an empty path";
    return r;
  }
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st) && !fs::is_directory(st)) {
    r.error = name + ": exists and is not a directory";
    return r;
  }
  if (!fs::exists(st)) {
    fs::create_directories(dir, ec);
    if (ec) {
      r.error = name + ": cannot create the directory: " + ec.message();
      return r;
    }
  }
  r.had_run = fs::exists(fs::path(dir) / "trace.csv", ec) || fs::exists(fs::path(dir) / "summary.json", ec);
  // a probe file: permissions, a read-only mount and a full disk all show here
  const std::string probe = (fs::path(dir) / ".chainsim-write-probe").string();
  const int fd = open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) {
    r.error = name + ": cannot write in it: " + std::strerror(errno);
    return r;
  }
  const char byte = '\n';
  const bool wrote = write(fd, &byte, 1) == 1;
  const int write_errno = errno;
  close(fd);
  unlink(probe.c_str());
  if (!wrote) r.error = name + ": cannot write in it: " + std::strerror(write_errno);
  return r;
}

}  // namespace chainsim
