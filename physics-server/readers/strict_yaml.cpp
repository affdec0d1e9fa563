// The strict YAML reader (strict_yaml.h).
#include "readers/strict_yaml.h"

#include "readers/safe_text.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

namespace chainsim {
namespace {

[[noreturn]] void raise_yaml_error(const std::string& message) { throw YamlError(message); }

// "'name'": how messages quote a key's path
std::string quoted(const std::string& name) { return "'" + name + "'"; }

std::string path_key(const std::string& path, const std::string& key) { return path + "." + key; }

}  // namespace

std::string join_names(const std::set<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

StrictYaml::StrictYaml(std::string file, YamlRaise raise)
    : file_(std::move(file)), raise_(raise ? raise : &raise_yaml_error) {}

std::string StrictYaml::read_file(const std::string& what) const {
  // checked before opening: a FIFO would block the open, a device never end
  std::error_code ec;
  const auto st = std::filesystem::status(file_, ec);
  if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
    fail_file("cannot read " + what + ": not a regular file (a directory, FIFO or device)");
  const auto size = std::filesystem::file_size(file_, ec);
  if (!ec && size > kMaxFileBytes)
    fail_file("cannot read " + what + ": " + std::to_string(size) + " bytes, over the limit of " +
              std::to_string(kMaxFileBytes));
  std::ifstream in(file_, std::ios::binary);
  if (!in) fail_file("cannot open " + what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

YAML::Node StrictYaml::parse(const std::string& text) const {
  try {
    // all documents are parsed, so a broken second one is a syntax error too
    const std::vector<YAML::Node> docs = YAML::LoadAll(text);
    if (docs.size() > 1) fail(docs[1], "a second YAML document ('---'): a file holds one");
    const YAML::Node root = docs.empty() ? YAML::Node() : docs[0];
    size_t budget = kMaxNodes;
    unique_keys(root, 0, &budget);
    return root;
  } catch (const YAML::Exception& e) {
    std::ostringstream s;
    s << file_;
    if (e.mark.line >= 0) s << ":" << (e.mark.line + 1) << ":" << (e.mark.column + 1);
    s << ": YAML syntax error: " << shown_text_cut(e.msg);  // it may quote a raw byte of the file
    raise_(s.str());
    throw YamlError(s.str());  // a raise that returned
  }
}

void StrictYaml::unique_keys(const YAML::Node& n, int depth, size_t* budget) const {
  if (depth > kMaxDepth) fail(n, "nested deeper than " + std::to_string(kMaxDepth) + " levels");
  if (*budget == 0) fail(n, "more than " + std::to_string(kMaxNodes) + " values (aliases counted as copies)");
  --*budget;
  if (n.IsSequence()) {
    for (const auto& item : n) unique_keys(item, depth + 1, budget);
  } else if (n.IsMap()) {
    std::map<std::string, YAML::Mark> seen;
    for (const auto& kv : n) {
      // every loader reads keys as text: a list, a mapping or null as a key is refused here, once
      if (!kv.first.IsScalar())
        fail(kv.first.Mark().line >= 0 ? kv.first : n,
             std::string("a key must be text, not ") +
                 (kv.first.IsSequence() ? "a list" : kv.first.IsMap() ? "a mapping" : "null"));
      const auto [it, fresh] = seen.emplace(kv.first.Scalar(), kv.first.Mark());
      if (!fresh)
        fail(kv.first, "duplicate key '" + kv.first.Scalar() + "' (first at line " +
                           std::to_string(it->second.line + 1) + ", column " + std::to_string(it->second.column + 1) +
                           ")");
      unique_keys(kv.second, depth + 1, budget);
    }
  }
}

std::string StrictYaml::where(const YAML::Node& n) const {
  std::ostringstream s;
  s << file_;
  const YAML::Mark m = n.Mark();
  if (m.line >= 0) s << ":" << (m.line + 1) << ":" << (m.column + 1);
  return s.str();
}

void StrictYaml::fail(const YAML::Node& n, const std::string& what) const {
  // escaped: a key or value with ESC or a newline must not reach the terminal raw
  const std::string message = shown_text(where(n) + ": " + what);
  raise_(message);
  throw YamlError(message);  // a raise that returned
}

void StrictYaml::fail_file(const std::string& what) const {
  const std::string message = shown_text(file_ + ": " + what);
  raise_(message);
  throw YamlError(message);
}

void StrictYaml::keys(const YAML::Node& map, const std::string& path,
                      const std::set<std::string>& allowed) const {
  if (!map.IsMap()) fail(map, quoted(path) + " must be a mapping");
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (!allowed.count(key))
      fail(kv.first, "unknown key '" + key + "' in " + quoted(path) + " (known: " + join_names(allowed) + ")");
  }
}

double StrictYaml::number_at(const YAML::Node& n, const std::string& name, double lo, double hi,
                             bool lo_open) const {
  if (!n.IsScalar()) fail(n, quoted(name) + " must be a number");
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(n, quoted(name) + " must be a number, not '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(n, quoted(name) + " must be a finite number, not '" + n.Scalar() + "'");
  const std::string is = quoted(name) + " = " + n.Scalar();
  if (lo_open && lo == 0 && !(v > 0)) fail(n, is + " must be > 0");
  if (v < lo || v > hi || (lo_open && v <= lo)) {
    std::ostringstream s;
    s << is << " is out of range " << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
    fail(n, s.str());
  }
  return v;
}

double StrictYaml::number(const YAML::Node& map, const std::string& key, double dflt, double lo, double hi,
                          const std::string& path, bool lo_open) const {
  const YAML::Node n = map[key];
  return n ? number_at(n, path_key(path, key), lo, hi, lo_open) : dflt;
}

double StrictYaml::positive(const YAML::Node& map, const std::string& key, double dflt, double hi,
                            const std::string& path) const {
  return number(map, key, dflt, 0.0, hi, path, true);
}

int64_t StrictYaml::integer_at(const YAML::Node& n, const std::string& name, int64_t lo, int64_t hi) const {
  if (!n.IsScalar()) fail(n, quoted(name) + " must be an integer");
  int64_t v = 0;
  try {
    v = n.as<int64_t>();
  } catch (const YAML::Exception&) {
    fail(n, quoted(name) + " must be an integer, not '" + n.Scalar() + "'");
  }
  if (v < lo || v > hi)
    fail(n, quoted(name) + " = " + n.Scalar() + " is out of range [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
  return v;
}

int64_t StrictYaml::integer(const YAML::Node& map, const std::string& key, int64_t dflt, int64_t lo, int64_t hi,
                            const std::string& path) const {
  const YAML::Node n = map[key];
  return n ? integer_at(n, path_key(path, key), lo, hi) : dflt;
}

std::string StrictYaml::string_at(const YAML::Node& n, const std::string& name) const {
  if (!n.IsScalar()) fail(n, quoted(name) + " must be a string");
  if (!is_printable_text(n.Scalar()))
    fail(n, quoted(name) + " must be printable UTF-8 text, not '" + n.Scalar() + "'");
  return n.Scalar();
}

std::string StrictYaml::name(const YAML::Node& map, const std::string& key, const std::string& dflt,
                             const std::string& path) const {
  const YAML::Node n = map[key];
  if (!n) return dflt;
  const std::string s = string_at(n, path_key(path, key));
  if (!is_path_name(s)) fail(n, quoted(path_key(path, key)) + " = '" + s + "' must be " + kPathNameRule);
  return s;
}

std::string StrictYaml::string(const YAML::Node& map, const std::string& key, const std::string& dflt,
                               const std::string& path) const {
  const YAML::Node n = map[key];
  return n ? string_at(n, path_key(path, key)) : dflt;
}

std::string StrictYaml::text(const YAML::Node& map, const std::string& key, const std::string& dflt,
                             const std::string& path) const {
  const YAML::Node n = map[key];
  if (!n) return dflt;
  if (!n.IsScalar() || n.Scalar().empty()) fail(n, quoted(path_key(path, key)) + " must be a non-empty string");
  return string_at(n, path_key(path, key));
}

bool StrictYaml::flag(const YAML::Node& map, const std::string& key, bool dflt, const std::string& path) const {
  const YAML::Node n = map[key];
  if (!n) return dflt;
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    fail(n, quoted(path_key(path, key)) + " must be true or false");
  }
}

Eigen::Vector3d StrictYaml::vec3(const YAML::Node& map, const std::string& key, const Eigen::Vector3d& dflt,
                                 const std::string& path, double limit) const {
  const YAML::Node n = map[key];
  if (!n) return dflt;
  return vec3_at(n, path_key(path, key), limit);
}

Eigen::Vector3d StrictYaml::vec3_at(const YAML::Node& n, const std::string& name, double limit) const {
  if (!n.IsSequence() || n.size() != 3) fail(n, quoted(name) + " must be a list of 3 numbers [x, y, z]");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = number_at(n[i], name + "[" + std::to_string(i) + "]", -limit, limit);
  return v;
}

std::string StrictYaml::choice(const YAML::Node& map, const std::string& key, const std::string& dflt,
                               const std::vector<std::string>& choices, const std::string& path) const {
  const std::string v = text(map, key, dflt, path);
  std::string known;
  for (const auto& c : choices) {
    if (c == v) return v;
    known += (known.empty() ? "" : ", ") + c;
  }
  fail(map[key], quoted(path_key(path, key)) + " '" + v + "' is not known (known: " + known + ")");
}

}  // namespace chainsim
