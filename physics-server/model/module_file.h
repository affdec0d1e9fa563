// Module definition files: YAML that maps 1:1 onto a ModuleDef
// (module_library.h). The format is docs/module-format.md; the built-in types
// are scenes/modules/*.yaml, compiled into the binary. Keys are strict: an
// unknown or misplaced key, a wrong type, a name that refers to nothing is an
// error naming file:line:column and the key.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "model/module_def.h"

namespace chainsim {

// "<file>:<line>:<column>: <what>"
class ModuleFileError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// parse a module definition and validate it (validate_module_def); `file` is
// used in messages
ModuleDef load_module_text(const std::string& text, const std::string& file);
ModuleDef load_module_file(const std::string& path);

// a shipped file: scenes/modules/<name>.yaml (generated builtin_modules.cpp)
struct BuiltinModuleFile {
  const char* name;  // the file's stem, which is its type name
  const char* path;  // "scenes/modules/<name>.yaml", for messages
  const char* text;
};
const std::vector<BuiltinModuleFile>& builtin_module_files();

}  // namespace chainsim
