// What the PIC build left beside a program's .hex: the .cod gpsim loads
// (code, symbols, the assembly lines of each instruction), the gplink .map
// (where each function and the software stack are) and the .pic.json
// (flash, RAM and stack use, the servo outputs it was built for). Read once
// when the module process starts; every missing or unreadable file is an
// error that names it and the build that makes it.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim::pic {

class BuildError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PicBuild {
  std::string hex, cod, map, json;          // the files' paths
  uint32_t flash_bytes = 0, flash_total = 0;
  uint32_t ram_bytes = 0, ram_total = 0, stack_bytes = 0;
  int servos = 0;                           // HAL_PIC_SERVOS of the build
  std::map<std::string, uint32_t> code;     // program-memory symbols: name -> byte address
  // code labels by address, as a backtrace names them: a C function's "_name"
  // as name, the runtime's labels (__startup, __mulint) as they are; with
  // the SDCC assembly file the map says each comes from
  struct Label {
    std::string name, asm_file;
  };
  std::map<uint32_t, Label> functions;
  std::map<std::string, uint32_t> data;     // data-memory symbols: name -> address
  std::map<uint32_t, uint32_t> section_size;  // program-memory section: address -> bytes

  // the address of a code symbol, or -1
  int64_t code_at(const std::string& name) const;
  // the label at or before byte address pc: a function's name ("?" if none)
  std::string function_at(uint32_t pc) const;
  // the assembly file of that label ("" if none)
  std::string asm_file_at(uint32_t pc) const;
};

// the build beside hex_path (PROG.hex -> PROG.cod, PROG.map, PROG.pic.json)
PicBuild load_pic_build(const std::string& hex_path);

// the map's symbol and section tables (exposed for tests)
void parse_gplink_map(const std::string& text, PicBuild* b);

// The C source line an instruction came from: gpsim knows the assembly file
// and line of each instruction (from the .cod); SDCC writes the C line above
// the instructions it made (";\t.line\tN; FILE\tTEXT"). Files are read once.
class SourceLines {
 public:
  struct Where {
    std::string file;  // the C file, as SDCC named it
    int line = 0;
    std::string text;  // the line's text, as SDCC quoted it
  };
  // the C line above asm_line of asm_file; false when there is none (the
  // file is gone, or the instruction is the runtime's assembly)
  bool find(const std::string& asm_file, int asm_line, Where* out);

 private:
  std::map<std::string, std::vector<std::string>> files_;
};

}  // namespace chainsim::pic
