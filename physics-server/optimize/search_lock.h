// The lock on a search's directory (DIR/lock, flock): held by the process
// that runs, resumes or verifies the search there, and released by the
// kernel when it ends however it ends. A second process on the directory is
// refused with the holder's pid instead of writing beside it.
#pragma once

#include <stdexcept>
#include <string>

namespace chainsim {

struct SearchLockError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class SearchLock {
 public:
  // creates dir if needed; throws SearchLockError when another process holds it
  explicit SearchLock(const std::string& dir);
  ~SearchLock();
  SearchLock(const SearchLock&) = delete;
  SearchLock& operator=(const SearchLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace chainsim
