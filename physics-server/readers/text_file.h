// A whole file's text, for readers that parse it themselves.
#pragma once

#include <string>

namespace chainsim {

// the file's bytes; throws std::runtime_error "PATH: cannot open" when it
// cannot be opened
std::string read_text_file(const std::string& path);

}  // namespace chainsim
