// A test file (docs/testing.md): a scene, how long and with which seeds to
// run it, edits of its keys and program parameters, and the expectations.
// Read strictly, as scene files are: every error is "file:line:column: what"
// and an unknown key is named with the known ones.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "testing/expectation.h"

namespace chainsim {

// a malformed test file, or a scene the test's edits make invalid
struct TestFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct TestExpectation {
  Expectation expectation;
  std::string where;  // file:line:column of the expectation in the test file
};

// one change to the scene's YAML: a key of `overrides:` or a program parameter
// of `params:`; path is a chain of map keys, where "chain" is followed by a
// module index (or "*" for every module)
struct SceneEdit {
  std::vector<std::string> path;
  YAML::Node value;
  std::string where;  // file:line:column in the test file
};

struct TestFile {
  std::string file;          // as found
  std::string name;
  std::string description;
  std::string scene_file;    // the scene, resolved against the test file's folder
  std::string scene_where;
  std::vector<uint64_t> seeds;  // empty: the scene's own seed
  std::string seeds_where;
  std::string on_module_fault = "stop";  // or "limp"
  std::vector<SceneEdit> edits;          // duration_s, overrides, params, in that order
  std::vector<TestExpectation> expect;
};

// reads a test file; throws TestFileError
TestFile load_test_file(const std::string& path);
TestFile load_test_text(const std::string& text, const std::string& name);

// "A..B" (A <= B, at most 10000 seeds) or one seed; throws std::invalid_argument
std::vector<uint64_t> parse_seed_range(const std::string& text);

// the scene a test runs with a seed (nullopt: the scene's own): the scene file
// with the test's edits applied. A scene file error is reported as the scene
// loader words it; an edit that makes the scene invalid is reported at the
// edit's place in the test file. check, if given, is part of loading: a
// SceneError it throws (e.g. check_scene_programs: a parameter the program
// does not declare) is reported the same way. Throws TestFileError.
using LoadedSceneCheck = std::function<void(const Scene&)>;
Scene load_test_scene(const TestFile& test, std::optional<uint64_t> seed, const LoadedSceneCheck& check = {});

// the test files among paths: files as given, folders searched recursively
// for *.test.yaml (sorted); throws TestFileError for a path that does not exist
std::vector<std::string> find_test_files(const std::vector<std::string>& paths);

}  // namespace chainsim
