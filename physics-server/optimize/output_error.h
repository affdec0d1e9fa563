// A file of the search's directory could not be written (a full disk, an
// I/O error): the search stops with exit code 5 and the file's name, as
// `chainsim run` does; nothing already written is lost.
#pragma once

#include <stdexcept>
#include <string>

namespace chainsim {

struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// writes text to path through a temporary file renamed over it, flushed and
// checked; throws OutputError naming the file
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace chainsim
