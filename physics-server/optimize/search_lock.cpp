#include "optimize/search_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

namespace chainsim {

SearchLock::SearchLock(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const std::string path = dir + "/lock";
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw SearchLockError(path + ": cannot open: " + std::strerror(errno));
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char holder[32] = {};
    const ssize_t n = pread(fd_, holder, sizeof holder - 1, 0);
    close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK)
      throw SearchLockError(dir + " is in use by another chainsim optimize" +
                            (n > 0 ? " (pid " + std::string(holder, static_cast<size_t>(n)) + ")" : std::string()) +
                            ": wait for it to end, or use another --out");
    throw SearchLockError(path + ": cannot lock: " + std::strerror(err));
  }
  const std::string pid = std::to_string(getpid());
  if (ftruncate(fd_, 0) == 0) (void)!pwrite(fd_, pid.data(), pid.size(), 0);
}

SearchLock::~SearchLock() {
  if (fd_ >= 0) close(fd_);  // releases the lock
}

}  // namespace chainsim
