// A whole file's text. See text_file.h.
#include "readers/text_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace chainsim {

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace chainsim
