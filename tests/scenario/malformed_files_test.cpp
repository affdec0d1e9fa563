// The fault-injection suite, malformed files of the design search, the test
// runner and calibrate (docs/reliability.md): mutated problem files
// (scenes/optimize/), test files (every shipped *.test.yaml), measured servo
// records and speed tables (calibrate's records), and, for each reader, the
// special files that once blocked or exhausted it. Each case is loaded by the
// library the command uses (load_problem_file, load_test_file and
// load_test_scene, read_measured, read_speed_table): it must load, or be
// refused with the reader's own error, one printable line that names the
// mutated file (at line:column where the file has one) or a file it refers
// to. Any other exception, a crash or a hang fails the suite. The unmutated
// files load first: if they do not, the harness is wrong, not the files.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>

#include "analysis/calibration/measured_record.h"
#include "analysis/calibration/servo_calibration.h"
#include "analysis/robot_calibration/speed_table.h"
#include "input_mutator.h"
#include "optimize/problem.h"
#include "readers/csv_table.h"
#include "scenario_util.h"
#include "testing/test_file.h"

using namespace scenario;
namespace fs = std::filesystem;

namespace {

constexpr uint64_t kSeed = 41;

// how one case ended
struct CaseEnd {
  bool accepted = false;
  std::string message;  // the refusal
  std::string wrong;    // what is wrong with how it ended ("" when nothing)
  bool at_position = false;
};

// the refusal must be the reader's own error (Err), one printable line of
// at most 4 KiB, naming `file` (at line:column, or just the file) or a file
// of the case's directory `dir` that it refers to
template <class Err>
CaseEnd load_case(const std::string& file, const std::string& dir, const std::function<void()>& load) {
  CaseEnd o;
  try {
    load();
    o.accepted = true;
    return o;
  } catch (const Err& e) {
    o.message = e.what();
  } catch (const std::exception& e) {
    o.wrong = std::string("an exception not of the reader's kind: ") + e.what();
    return o;
  } catch (...) {
    o.wrong = "an exception that is no std::exception";
    return o;
  }
  for (unsigned char c : o.message)
    if (c < 0x20 || c == 0x7f) {
      o.wrong = "a control byte in the message";
      return o;
    }
  if (o.message.size() > 4096) o.wrong = "a message of " + std::to_string(o.message.size()) + " bytes";
  const size_t at = o.message.find(file + ":");
  static const std::regex kPos("^:[0-9]+:[0-9]+: ");
  o.at_position = at != std::string::npos && std::regex_search(o.message.substr(at + file.size()), kPos);
  if (at == std::string::npos && o.message.find(dir + "/") == std::string::npos)
    o.wrong = "the refusal names no file of the case";
  return o;
}

// the counts a reader's cases print and docs/reliability.md quotes
struct Tally {
  int cases = 0, accepted = 0, at_position = 0, naming_file = 0;
  std::map<std::string, std::pair<int, int>> by_kind;  // accepted, refused

  void add(const std::string& kind, const CaseEnd& o, const std::string& about) {
    ++cases;
    EXPECT_EQ(o.wrong, "") << about << "\n  " << o.message;
    if (std::getenv("CHAINSIM_FUZZ_VERBOSE"))
      std::printf("%s: %s\n", about.c_str(), o.accepted ? "accepted" : o.message.c_str());
    auto& k = by_kind[kind];
    if (o.accepted) {
      ++accepted;
      ++k.first;
      return;
    }
    ++k.second;
    ++(o.at_position ? at_position : naming_file);
  }
  void print(const std::string& what) const {
    std::printf("%s: %d cases (seed %llu): %d accepted, %d refused (%d at file:line:column, %d naming a file)\n",
                what.c_str(), cases, static_cast<unsigned long long>(kSeed), accepted, cases - accepted, at_position,
                naming_file);
    for (const auto& [kind, n] : by_kind)
      std::printf("  %-15s accepted %3d, refused %3d\n", kind.c_str(), n.first, n.second);
  }
};

// the special files every reader must refuse by name without reading them:
// a device that never ends, a FIFO that would block, a folder, and a regular
// file past the reader's size bound
void special_files(const fs::path& dir, uintmax_t over_bytes, const std::string& ext,
                   const std::function<CaseEnd(const std::string& file)>& load, Tally* t) {
  fs::create_directories(dir);
  const std::string fifo = (dir / ("fifo" + ext)).string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string folder = (dir / ("folder" + ext)).string();
  fs::create_directory(folder);
  const std::string big = (dir / ("big" + ext)).string();
  {
    std::ofstream f(big);
    f << "# " << std::string(over_bytes, 'x') << "\n";
  }
  for (const std::string& f : {std::string("/dev/zero"), fifo, folder, big}) {
    const CaseEnd o = load(f);
    EXPECT_FALSE(o.accepted) << f;
    t->add("special file", o, "special file " + f);
  }
}

// a copy of the repository's scenes/ under root/scenes, so that the relative
// paths of problem and test files resolve as in the repository
fs::path mirror(const std::string& name) {
  const fs::path root = temp_dir(name);
  const fs::path repo_scenes = fs::path(scene_path("default")).parent_path();
  fs::copy(repo_scenes, root / "scenes", fs::copy_options::recursive);
  return root;
}

std::string source_dir() { return fs::path(scene_path("default")).parent_path().parent_path().string(); }

}  // namespace

TEST(FaultInjection, CsvMutatorIsSeededAndChangesTheRecord) {
  const std::string text = read_file(source_dir() + "/scenes/measured/helicoidal_speed_vs_slope.csv");
  for (int k = 0; k < kCsvMutationKinds; ++k)
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      const auto kind = static_cast<CsvMutationKind>(k);
      const Mutation a = mutate_csv(text, kind, seed), b = mutate_csv(text, kind, seed);
      EXPECT_EQ(a.text, b.text) << csv_mutation_name(kind) << " seed " << seed;
      EXPECT_NE(a.text, text) << csv_mutation_name(kind) << " seed " << seed << ": " << a.what;
    }
}

// 120 mutated problem files from the shipped problems (scenes/optimize/*.yaml
// with a genome), and the special files
TEST(FaultInjection, MutatedProblemFilesLoadOrAreRefusedNamingTheFile) {
  const fs::path root = mirror("mutated-problems");
  const fs::path dir = root / "scenes" / "optimize";
  std::vector<fs::path> shipped;
  for (const auto& de : fs::directory_iterator(dir))
    if (de.path().extension() == ".yaml" && read_file(de.path().string()).find("\ngenome:") != std::string::npos)
      shipped.push_back(de.path());  // a problem, not a scene of one
  std::sort(shipped.begin(), shipped.end());
  ASSERT_GE(shipped.size(), 5u);
  for (const fs::path& p : shipped) ASSERT_NO_THROW(chainsim::load_problem_file(p.string())) << "control " << p;

  Tally t;
  SplitMix pick(kSeed);
  for (int i = 0; i < 120; ++i) {
    const fs::path& in = shipped[pick.below(shipped.size())];
    const auto kind = static_cast<MutationKind>(i % kMutationKinds);
    const Mutation m = mutate(read_file(in.string()), kind, pick.next());
    const std::string file = (dir / ("m" + std::to_string(i) + "-" + in.filename().string())).string();
    if (!m.drop_file) std::ofstream(file) << m.text;
    const CaseEnd o = load_case<chainsim::ProblemError>(file, root.string(),
                                                        [&] { chainsim::load_problem_file(file); });
    t.add(mutation_name(kind), o, "case " + std::to_string(i) + " (" + mutation_name(kind) + " of " +
                                      in.filename().string() + ": " + m.what + ", " + file + ")");
  }
  special_files(root / "special", 17u << 20, ".yaml", [&](const std::string& f) {
    return load_case<chainsim::ProblemError>(f, root.string(), [&] { chainsim::load_problem_file(f); });
  }, &t);
  t.print("mutated problem files");
  fs::remove_all(root);
}

// 120 mutated test files from every shipped *.test.yaml, each with its scene
// and edits loaded as `chainsim test` loads them, and the special files
TEST(FaultInjection, MutatedTestFilesLoadOrAreRefusedNamingTheFile) {
  const fs::path root = mirror("mutated-tests");
  const fs::path src = source_dir();
  std::vector<fs::path> shipped;  // relative to the source tree
  for (const char* top : {"tests", "docs"})
    for (const auto& de : fs::recursive_directory_iterator(src / top)) {
      const std::string f = de.path().string();
      // the test runner's own malformed examples excepted
      if (f.size() > 10 && f.compare(f.size() - 10, 10, ".test.yaml") == 0 && f.find("/malformed/") == std::string::npos)
        shipped.push_back(fs::relative(de.path(), src));
    }
  std::sort(shipped.begin(), shipped.end());
  ASSERT_GE(shipped.size(), 20u);
  // each test file's folder with its scenes beside it
  for (const fs::path& rel : shipped) {
    fs::create_directories(root / rel.parent_path());
    for (const auto& de : fs::directory_iterator(src / rel.parent_path()))
      if (de.is_regular_file()) fs::copy_file(de.path(), root / rel.parent_path() / de.path().filename(),
                                              fs::copy_options::skip_existing);
  }
  const auto load = [](const std::string& file) {
    const chainsim::TestFile tf = chainsim::load_test_file(file);
    chainsim::load_test_scene(tf, std::nullopt);
  };
  for (const fs::path& rel : shipped) ASSERT_NO_THROW(load((root / rel).string())) << "control " << rel;

  Tally t;
  SplitMix pick(kSeed);
  for (int i = 0; i < 120; ++i) {
    const fs::path& rel = shipped[pick.below(shipped.size())];
    const auto kind = static_cast<MutationKind>(i % kMutationKinds);
    const Mutation m = mutate(read_file((src / rel).string()), kind, pick.next());
    const std::string file = (root / rel.parent_path() / ("m" + std::to_string(i) + ".test.yaml")).string();
    if (!m.drop_file) std::ofstream(file) << m.text;
    const CaseEnd o = load_case<chainsim::TestFileError>(file, root.string(), [&] { load(file); });
    t.add(mutation_name(kind), o, "case " + std::to_string(i) + " (" + mutation_name(kind) + " of " + rel.string() +
                                      ": " + m.what + ", " + file + ")");
  }
  special_files(root / "special", 17u << 20, ".test.yaml", [&](const std::string& f) {
    return load_case<chainsim::TestFileError>(f, root.string(), [&] { load(f); });
  }, &t);
  t.print("mutated test files");
  fs::remove_all(root);
}

// calibrate's records: 100 mutated measured servo records (a synthetic step
// response) and 60 mutated speed tables (the shipped scenes/measured/), and
// the special files of each reader
TEST(FaultInjection, MutatedRecordsAreReadOrRefusedNamingTheFile) {
  const fs::path root = temp_dir("mutated-records");
  std::string measured = "t_s,setpoint_deg,angle_deg,current_a\n";  // a step response, as a bench records it
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.001 * i, sp = t < 0.1 ? 30 : 120;
    const double angle = t < 0.1 ? 30 : 120 - 90 * std::exp(-(t - 0.1) / 0.05);
    char line[96];
    std::snprintf(line, sizeof line, "%.3f,%.0f,%.4f,%.3f\n", t, sp, angle, t < 0.1 ? 0.05 : 0.05 + 0.5 * (120 - angle) / 90);
    measured += line;
  }
  const std::string measured_file = write_file(root.string(), "control-measured.csv", measured);
  ASSERT_NO_THROW(chainsim::read_measured(measured_file, chainsim::kMinMeasuredRows));
  std::vector<std::string> tables;
  for (const char* name : {"helicoidal_speed_vs_slope.csv", "inchworm_speed_vs_slope.csv"}) {
    tables.push_back(read_file(source_dir() + "/scenes/measured/" + name));
    ASSERT_NO_THROW(chainsim::read_speed_table(source_dir() + "/scenes/measured/" + name)) << name;
  }

  const auto read_m = [](const std::string& f) { chainsim::read_measured(f, chainsim::kMinMeasuredRows); };
  const auto read_t = [](const std::string& f) { chainsim::read_speed_table(f); };
  Tally tm, tt;
  SplitMix pick(kSeed);
  for (int i = 0; i < 160; ++i) {
    const bool table = i >= 100;
    const auto kind = static_cast<CsvMutationKind>(i % kCsvMutationKinds);
    const Mutation m = mutate_csv(table ? tables[pick.below(tables.size())] : measured, kind, pick.next());
    const std::string file = write_file(root.string(), "m" + std::to_string(i) + ".csv", m.text);
    const CaseEnd o = load_case<chainsim::CsvError>(file, root.string(), [&] { (table ? read_t : read_m)(file); });
    (table ? tt : tm).add(csv_mutation_name(kind), o, "case " + std::to_string(i) + " (" + csv_mutation_name(kind) +
                                                          ": " + m.what + ", " + file + ")");
    fs::remove(file);
  }
  special_files(root / "special-m", 33u << 20, ".csv", [&](const std::string& f) {
    return load_case<chainsim::CsvError>(f, root.string(), [&] { read_m(f); });
  }, &tm);
  special_files(root / "special-t", 33u << 20, ".csv", [&](const std::string& f) {
    return load_case<chainsim::CsvError>(f, root.string(), [&] { read_t(f); });
  }, &tt);
  tm.print("mutated measured records");
  tt.print("mutated speed tables");
  fs::remove_all(root);
}
