// The one strict reader of the project's YAML files (scenes, module types,
// bench files): every error starts with "file:line:column: ", an unknown key
// lists the known ones, a number is checked to be finite and in its range.
// Each loader keeps its own error type: the reader throws through `raise`.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>

#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

// the error the reader throws when its loader gives no `raise` of its own
class YamlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// throws the loader's error with this message ("file:line:column: what");
// must not return
using YamlRaise = void (*)(const std::string& message);

class StrictYaml {
 public:
  // bounds of every file: a position is within 10 km of the origin; a file
  // nests at most 64 levels and holds at most a million values
  static constexpr double kMaxCoordinateM = 1e4;
  static constexpr int kMaxDepth = 64;
  static constexpr size_t kMaxNodes = 1000000;
  // a YAML file is a regular file of at most 16 MiB
  static constexpr uintmax_t kMaxFileBytes = 16u << 20;

  // `file` is used in messages; `raise` throws the loader's error type
  explicit StrictYaml(std::string file, YamlRaise raise = nullptr);

  const std::string& file() const { return file_; }

  // the whole text of a file; "file: cannot open <what>" when it cannot be
  // read, an error too when it is not a regular file or over kMaxFileBytes
  std::string read_file(const std::string& what) const;
  // parses text; a syntax error is "file:line:column: YAML syntax error: ...";
  // a second document, a key given twice in one mapping, or more nesting or
  // values than the bounds above is an error at the culprit's line and column
  YAML::Node parse(const std::string& text) const;

  // "file:line:column" of node n (just "file" when it has no position)
  std::string where(const YAML::Node& n) const;
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const;
  // "file: what", for errors with no node
  [[noreturn]] void fail_file(const std::string& what) const;

  // map must be a mapping whose keys are all in allowed; an unknown key names
  // the known ones. path names the map in messages ("environment.pipe").
  void keys(const YAML::Node& map, const std::string& path, const std::set<std::string>& allowed) const;

  // node n (named `name` in messages, e.g. "bodies[1].mass_kg") as a finite
  // number in [lo, hi], or (lo, hi] when lo_open
  double number_at(const YAML::Node& n, const std::string& name, double lo, double hi,
                   bool lo_open = false) const;
  // map[key] as number_at, or dflt when the key is absent
  double number(const YAML::Node& map, const std::string& key, double dflt, double lo, double hi,
                const std::string& path, bool lo_open = false) const;
  // a number > 0 and <= hi
  double positive(const YAML::Node& map, const std::string& key, double dflt, double hi,
                  const std::string& path) const;
  // an integer in [lo, hi]
  int64_t integer_at(const YAML::Node& n, const std::string& name, int64_t lo, int64_t hi) const;
  int64_t integer(const YAML::Node& map, const std::string& key, int64_t dflt, int64_t lo, int64_t hi,
                  const std::string& path) const;
  // a scalar (may be empty)
  std::string string_at(const YAML::Node& n, const std::string& name) const;
  std::string string(const YAML::Node& map, const std::string& key, const std::string& dflt,
                     const std::string& path) const;
  // a non-empty scalar
  std::string text(const YAML::Node& map, const std::string& key, const std::string& dflt,
                   const std::string& path) const;
  // true or false
  bool flag(const YAML::Node& map, const std::string& key, bool dflt, const std::string& path) const;
  // [x, y, z], each finite and in [-limit, limit] (a coordinate in metres by default)
  Eigen::Vector3d vec3(const YAML::Node& map, const std::string& key, const Eigen::Vector3d& dflt,
                       const std::string& path, double limit = kMaxCoordinateM) const;
  Eigen::Vector3d vec3_at(const YAML::Node& n, const std::string& name, double limit = kMaxCoordinateM) const;
  // a text that is one of choices (listed in their order when it is not)
  std::string choice(const YAML::Node& map, const std::string& key, const std::string& dflt,
                     const std::vector<std::string>& choices, const std::string& path) const;

 private:
  void unique_keys(const YAML::Node& n, int depth, size_t* budget) const;

  std::string file_;
  YamlRaise raise_;
};

// "a, b, c"
std::string join_names(const std::set<std::string>& names);

}  // namespace chainsim
