// The files of a PIC build. See pic_build.h.
#include "pic-module/pic_build.h"

#include <sys/stat.h>

#include <cctype>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

namespace chainsim::pic {

namespace {

std::string read_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw BuildError(path + " (" + what + ") cannot be read: build the program for the PIC with "
                            "tools/pic-build.sh (or -DCHAINSIM_PIC=ON in your own project)");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string replace_ext(const std::string& path, const std::string& ext) {
  const size_t slash = path.rfind('/');
  const size_t dot = path.rfind('.');
  const std::string stem = (dot != std::string::npos && (slash == std::string::npos || dot > slash))
                               ? path.substr(0, dot) : path;
  return stem + ext;
}

}  // namespace

int64_t PicBuild::code_at(const std::string& name) const {
  const auto it = code.find(name);
  return it == code.end() ? -1 : static_cast<int64_t>(it->second);
}

std::string PicBuild::function_at(uint32_t pc) const {
  auto it = functions.upper_bound(pc);
  if (it == functions.begin()) return "?";
  return std::prev(it)->second.name;
}

std::string PicBuild::asm_file_at(uint32_t pc) const {
  auto it = functions.upper_bound(pc);
  if (it == functions.begin()) return "";
  return std::prev(it)->second.asm_file;
}

void parse_gplink_map(const std::string& text, PicBuild* b) {
  std::vector<std::pair<uint32_t, PicBuild::Label>> labels;
  std::istringstream in(text);
  std::string line;
  enum { None, Sections, Symbols } part = None;
  while (std::getline(in, line)) {
    if (line.find("Section Info") != std::string::npos) { part = Sections; continue; }
    if (line.find("Symbols") != std::string::npos && line.find("Symbols") < 40) { part = Symbols; continue; }
    if (line.find("Program Memory Usage") != std::string::npos) { part = None; continue; }
    std::istringstream f(line);
    std::string a, b2, c, d, e;
    if (part == Sections) {
      // name type 0xADDR program|data 0xSIZE
      if (!(f >> a >> b2 >> c >> d >> e) || c.rfind("0x", 0) != 0 || e.rfind("0x", 0) != 0) continue;
      if (d == "program") b->section_size[std::stoul(c, nullptr, 16)] = std::stoul(e, nullptr, 16);
    } else if (part == Symbols) {
      // name 0xADDR program|data static|extern file
      if (!(f >> a >> b2 >> c) || b2.rfind("0x", 0) != 0) continue;
      const uint32_t at = std::stoul(b2, nullptr, 16);
      if (c == "program") {
        b->code.emplace(a, at);
        std::string storage, file;
        f >> storage >> file;
        labels.emplace_back(at, PicBuild::Label{a, file});
      }
      else if (c == "data") b->data.emplace(a, at);
    }
  }
  // a function is a label that starts a code section (SDCC gives each
  // function its own, S_<file>__<name>); the others are inside one
  for (auto& [at, l] : labels) {
    if (!b->section_size.count(at) || b->functions.count(at)) continue;
    if (l.name.size() > 1 && l.name[0] == '_' && l.name[1] != '_') l.name.erase(0, 1);  // a C name
    b->functions.emplace(at, l);
  }
}

PicBuild load_pic_build(const std::string& hex_path) {
  PicBuild b;
  b.hex = hex_path;
  b.cod = replace_ext(hex_path, ".cod");
  b.map = replace_ext(hex_path, ".map");
  b.json = replace_ext(hex_path, ".pic.json");
  struct stat st {};
  if (stat(hex_path.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
    throw BuildError(hex_path + " not found: build the program for the PIC with tools/pic-build.sh "
                     "(or -DCHAINSIM_PIC=ON in your own project)");
  (void)read_file(b.cod, "gpsim's symbol file");
  parse_gplink_map(read_file(b.map, "the linker's map"), &b);
  if (b.code.empty()) throw BuildError(b.map + " holds no symbol table: rebuild the program");
  try {
    const auto j = nlohmann::json::parse(read_file(b.json, "the build's figures"));
    b.flash_bytes = j.at("flash_bytes").get<uint32_t>();
    b.flash_total = j.at("flash_total").get<uint32_t>();
    b.ram_bytes = j.at("ram_bytes").get<uint32_t>();
    b.ram_total = j.at("ram_total").get<uint32_t>();
    b.stack_bytes = j.at("stack_bytes").get<uint32_t>();
    b.servos = j.at("servos").is_null() ? -1 : j.at("servos").get<int>();
  } catch (const nlohmann::json::exception& e) {
    throw BuildError(b.json + ": " + e.what() + ": rebuild the program");
  }
  return b;
}

bool SourceLines::find(const std::string& asm_file, int asm_line, Where* out) {
  auto it = files_.find(asm_file);
  if (it == files_.end()) {
    std::vector<std::string> lines;
    std::ifstream in(asm_file);
    std::string l;
    while (std::getline(in, l)) lines.push_back(l);
    it = files_.emplace(asm_file, std::move(lines)).first;
  }
  const auto& lines = it->second;
  static const std::string kMark = ";\t.line\t";
  for (int i = std::min<int>(asm_line, static_cast<int>(lines.size())) - 1; i >= 0; --i) {
    const std::string& l = lines[static_cast<size_t>(i)];
    if (l.rfind(kMark, 0) != 0) continue;
    // ";\t.line\t55; /path/main.c\treturn ...;"
    const size_t semi = l.find(';', kMark.size());
    const size_t tab = semi == std::string::npos ? std::string::npos : l.find('\t', semi);
    if (semi == std::string::npos) return false;
    out->line = std::atoi(l.c_str() + kMark.size());
    out->file = l.substr(semi + 2, tab == std::string::npos ? std::string::npos : tab - semi - 2);
    out->text = tab == std::string::npos ? "" : l.substr(tab + 1);
    return true;
  }
  return false;
}

}  // namespace chainsim::pic
