// Test files: the keys, the seeds, the scene edits, and errors that name
// file:line:column (and the known keys) like the scene files' errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <sys/stat.h>

#include "testing/test_file.h"

using namespace chainsim;

namespace {

// the message of the TestFileError that loading text throws ("" if none)
std::string error_of(const std::string& text) {
  try {
    load_test_text(text, "dir/t.test.yaml");
  } catch (const TestFileError& e) {
    return e.what();
  }
  return "";
}

const std::string kDefault = std::string(CHAINSIM_SOURCE_DIR) + "/scenes/default.yaml";

std::string temp_dir() {
  char tmpl[] = "/tmp/chainsim-testfile-XXXXXX";
  return mkdtemp(tmpl);
}

std::string write(const std::string& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir + "/" + name) << text;
  return dir + "/" + name;
}

}  // namespace

TEST(TestFile, ReadsEveryKey) {
  const TestFile t = load_test_text(R"(name: forward
description: the default snake crawls forward
scene: ../scenes/default.yaml
duration_s: 6
seeds: [1, 2]
on_module_fault: limp
overrides:
  central: {params: {gait: 2}}
  chain: RRRR
params:
  modules: {control_ms: 5}
  m2: {control_ms: 20}
expect:
  - no_faults
  - "chain.distance_m >= 0.2"
)", "dir/t.test.yaml");
  EXPECT_EQ(t.name, "forward");
  EXPECT_EQ(t.scene_file, "scenes/default.yaml");  // relative to the test file's folder
  EXPECT_EQ(t.seeds, (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(t.on_module_fault, "limp");
  ASSERT_EQ(t.expect.size(), 2u);
  EXPECT_EQ(t.expect[1].where, "dir/t.test.yaml:15:6");  // inside the quotes
  // duration, two overrides, two parameters, in the file's order
  ASSERT_EQ(t.edits.size(), 5u);
  EXPECT_EQ(t.edits[0].path, (std::vector<std::string>{"duration_s"}));
  EXPECT_EQ(t.edits[1].path, (std::vector<std::string>{"central", "params", "gait"}));
  EXPECT_EQ(t.edits[1].where, "dir/t.test.yaml:8:22");
  EXPECT_EQ(t.edits[3].path, (std::vector<std::string>{"chain", "*", "params", "control_ms"}));
  EXPECT_EQ(t.edits[4].path, (std::vector<std::string>{"chain", "2", "params", "control_ms"}));
}

TEST(TestFile, SeedRanges) {
  EXPECT_EQ(parse_seed_range("3..5"), (std::vector<uint64_t>{3, 4, 5}));
  EXPECT_EQ(parse_seed_range("7"), (std::vector<uint64_t>{7}));
  EXPECT_THROW(parse_seed_range("5..3"), std::invalid_argument);
  EXPECT_THROW(parse_seed_range("a..3"), std::invalid_argument);
  EXPECT_THROW(parse_seed_range("1..20000"), std::invalid_argument);
  const TestFile t = load_test_text("name: a\nscene: s.yaml\nseeds: \"2..4\"\nexpect: [no_faults]\n", "t.yaml");
  EXPECT_EQ(t.seeds, (std::vector<uint64_t>{2, 3, 4}));
}

TEST(TestFile, ErrorsNameFileLineColumn) {
  const std::string head = "name: a\nscene: s.yaml\n";
  EXPECT_EQ(error_of(head + "expect: [no_faults]\ntimeout: 3\n"),
            "dir/t.test.yaml:4:1: unknown key 'timeout' in 'test' (known: description, duration_s, expect, name, "
            "on_module_fault, overrides, params, scene, seed, seeds)");
  EXPECT_EQ(error_of("name: a\nexpect: [no_faults]\n").rfind("dir/t.test.yaml:1:1: missing key 'scene'", 0), 0u);
  EXPECT_EQ(error_of(head + "expect: []\n"), "dir/t.test.yaml:3:9: 'expect' must be a non-empty list of expectations");
  EXPECT_EQ(error_of(head + "duration_s: -2\nexpect: [no_faults]\n"),
            "dir/t.test.yaml:3:13: 'test.duration_s' = -2 is out of range [0.001, 86400]");
  EXPECT_EQ(error_of(head + "seed: 1\nseeds: [2]\nexpect: [no_faults]\n"),
            "dir/t.test.yaml:4:8: give either 'seed' or 'seeds', not both");
  EXPECT_EQ(error_of(head + "params:\n  m1x: {a: 1}\nexpect: [no_faults]\n"),
            "dir/t.test.yaml:4:3: unknown key 'm1x' in 'params' (known: central, modules, m0, m1, ...)");
  EXPECT_EQ(error_of(head + "params:\n  central: {gait: fast}\nexpect: [no_faults]\n"),
            "dir/t.test.yaml:4:19: 'params.central.gait' must be an integer");
  EXPECT_EQ(error_of(head + "on_module_fault: retry\nexpect: [no_faults]\n"),
            "dir/t.test.yaml:3:18: 'test.on_module_fault' 'retry' is not known (known: stop, limp)");
  EXPECT_EQ(error_of(head + "expect: [no_faults]\nbad: [\n").rfind("dir/t.test.yaml:5:", 0), 0u);
}

// the strict reader's rules, as for scenes: a key given twice and a second
// document are errors at their place, not "the first value wins"
TEST(TestFile, DuplicateKeysAndSecondDocumentsAreRefused) {
  const std::string head = "name: a\nscene: s.yaml\n";
  EXPECT_EQ(error_of(head + "expect: [no_faults]\nname: b\n").rfind("dir/t.test.yaml:4:1: ", 0), 0u)
      << error_of(head + "expect: [no_faults]\nname: b\n");
  EXPECT_NE(error_of(head + "expect: [no_faults]\nname: b\n").find("'name'"), std::string::npos);
  EXPECT_EQ(error_of(head + "expect: [no_faults]\n---\nname: b\n").rfind("dir/t.test.yaml:5:", 0), 0u)
      << error_of(head + "expect: [no_faults]\n---\nname: b\n");
  EXPECT_NE(error_of(head + "expect: [no_faults]\n---\nname: b\n").find("second YAML document"), std::string::npos);
}

// a device, a FIFO or a file past the strict reader's 16 MiB is refused by
// name before it is read (a FIFO would block, /dev/zero never end)
TEST(TestFile, OnlyBoundedRegularFilesAreRead) {
  const auto error_loading = [](const std::string& path) -> std::string {
    try {
      load_test_file(path);
    } catch (const TestFileError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_loading("/dev/zero"), "/dev/zero: cannot read test file: not a regular file (a directory, FIFO or device)");
  const std::string dir = temp_dir();
  ASSERT_EQ(mkfifo((dir + "/f.test.yaml").c_str(), 0600), 0);
  EXPECT_NE(error_loading(dir + "/f.test.yaml").find("not a regular file"), std::string::npos);
  {
    std::ofstream big(dir + "/big.test.yaml");
    big << "name: a\n#" << std::string(17u << 20, 'x') << "\n";
  }
  EXPECT_NE(error_loading(dir + "/big.test.yaml").find("over the limit of 16777216"), std::string::npos)
      << error_loading(dir + "/big.test.yaml");
  std::filesystem::remove_all(dir);
}

TEST(TestFile, ExpectationErrorsPointIntoTheLine) {
  const std::string head = "name: a\nscene: s.yaml\nexpect:\n  - no_faults\n";
  // plain, double-quoted and single-quoted: the column of the bad word in the file
  EXPECT_EQ(error_of(head + "  - chain.distance_m => 0.2\n"),
            "dir/t.test.yaml:5:22: expected a comparison (<, <=, >, >=, ==, != or between), got '=>' in "
            "\"chain.distance_m => 0.2\"");
  EXPECT_EQ(error_of(head + "  - \"trace.m0.s0.current_a maxx < 0.35\"\n").rfind("dir/t.test.yaml:5:28: ", 0), 0u);
  EXPECT_EQ(error_of(head + "  - 'log m0 /contact before 8'\n").rfind("dir/t.test.yaml:5:13: ", 0), 0u);
  // the same text twice in the line: the second one is at fault
  EXPECT_EQ(error_of(head + "  - \"trace.m0.x > 0.1 before 0.1 0.1\"\n").rfind("dir/t.test.yaml:5:34: unexpected", 0), 0u);
  // escapes before the fault are written longer than they read: \\( is one character
  EXPECT_EQ(error_of(head + "  - \"log central /chain: \\\\(R\\\\) (R)\\\\1/ never\"\n")
                .rfind("dir/t.test.yaml:5:37: unsupported pattern /chain: \\(R\\) (R)\\1/: '\\1' is a "
                       "backreference",
                       0),
            0u);
  EXPECT_EQ(error_of(head + "  - 'log m0 /it''s(?=x)/ never'\n").rfind("dir/t.test.yaml:5:19: unsupported", 0), 0u);
  EXPECT_EQ(error_of(head + "  - {a: 1}\n"),
            "dir/t.test.yaml:5:5: an expectation must be one line of text, e.g. \"chain.distance_m >= 0.2\"");
}

TEST(TestFile, SceneEditsApplyAndTheirErrorsNameTheTestFile) {
  const std::string dir = temp_dir();
  const std::string head = "name: a\nscene: " + kDefault + "\n";
  // overrides and parameters reach the scene; a chain string becomes a list to take them
  const std::string ok = write(dir, "ok.test.yaml", head + R"(duration_s: 2.5
overrides:
  chain: RRH
params:
  central: {gait: 0}
  modules: {control_ms: 7}
  m1: {control_ms: 9}
expect: [no_faults]
)");
  const TestFile t = load_test_file(ok);
  const Scene s = load_test_scene(t, 42);
  EXPECT_DOUBLE_EQ(s.duration_s, 2.5);
  EXPECT_EQ(s.world.seed, 42u);
  ASSERT_EQ(s.modules.size(), 3u);
  EXPECT_EQ(s.modules[2].type, "helicoidal");
  EXPECT_EQ(s.modules[0].params.at("control_ms"), 7);
  EXPECT_EQ(s.modules[1].params.at("control_ms"), 9);
  EXPECT_EQ(s.central.params.at("gait"), 0);
  EXPECT_EQ(s.central.params.at("amplitude_cdeg"), 2000);  // the rest of the scene stays
  EXPECT_EQ(load_test_scene(t, std::nullopt).world.seed, 1u);  // the scene's own

  // an unknown scene key given in overrides is reported where the test file has it
  const std::string bad = write(dir, "bad.test.yaml", head + "overrides:\n  physics: {dt_us: 500, substeps: 2}\nexpect: [no_faults]\n");
  try {
    load_test_scene(load_test_file(bad), std::nullopt);
    FAIL() << "no error";
  } catch (const TestFileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad + ":4:25: unknown key 'substeps' in 'physics'", 0), 0u) << e.what();
  }
  // a module the chain does not have
  const std::string m9 = write(dir, "m9.test.yaml", head + "params:\n  m9: {control_ms: 5}\nexpect: [no_faults]\n");
  try {
    load_test_scene(load_test_file(m9), std::nullopt);
    FAIL() << "no error";
  } catch (const TestFileError& e) {
    EXPECT_EQ(std::string(e.what()), m9 + ":4:8: m9: the chain has 8 modules (m0..m7)");
  }
  // a scene that does not load is reported with its own file:line:column
  const std::string scene = write(dir, "broken.yaml", "name: x\nchain: RXR\n");
  const std::string b = write(dir, "b.test.yaml", "name: b\nscene: broken.yaml\nexpect: [no_faults]\n");
  try {
    load_test_scene(load_test_file(b), std::nullopt);
    FAIL() << "no error";
  } catch (const TestFileError& e) {
    EXPECT_NE(std::string(e.what()).find(b + ":2:8: the scene does not load: " + scene + ":2:8: 'chain' has unknown module letter 'X'"),
              std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(TestFile, FoldersAreSearchedForTestFiles) {
  const std::string dir = temp_dir();
  std::filesystem::create_directories(dir + "/sub");
  write(dir, "b.test.yaml", "");
  write(dir, "sub/a.test.yaml", "");
  write(dir, "scene.yaml", "");
  const auto files = find_test_files({dir});
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0], dir + "/b.test.yaml");
  EXPECT_EQ(files[1], dir + "/sub/a.test.yaml");
  EXPECT_THROW(find_test_files({dir + "/missing"}), TestFileError);
  std::filesystem::remove_all(dir);
}

// a symbolic link that loops, under a test file's name, is named; a link to a
// folder is not followed (a loop of folders cannot recurse)
TEST(TestFile, LinksInFoldersAreNamedNotFollowed) {
  const std::string dir = temp_dir();
  write(dir, "a.test.yaml", "");
  std::filesystem::create_directory_symlink(dir, dir + "/again");
  EXPECT_EQ(find_test_files({dir}), std::vector<std::string>{dir + "/a.test.yaml"});
  std::filesystem::create_symlink(dir + "/loop.test.yaml", dir + "/loop.test.yaml");
  try {
    find_test_files({dir});
    ADD_FAILURE() << "a looping link was accepted";
  } catch (const TestFileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir + "/loop.test.yaml: cannot read this test file: ", 0), 0u) << e.what();
  }
  std::filesystem::remove_all(dir);
}
