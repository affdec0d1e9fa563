// `chainsim test` end to end with real runs: the test files in testfiles/
// (a passing one, a failing one with two seeds, malformed ones), the exit
// codes, one line per test and seed, the JUnit XML parsed back, the failed
// runs kept with replay.html and a picture of the failure; log patterns a
// backtracking engine never finishes; SIGINT and SIGTERM during a run.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <thread>

#include "scenario_util.h"

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;
namespace pt = boost::property_tree;

namespace {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string temp_dir() {
  char tmpl[] = "/tmp/chainsim-testcmd-XXXXXX";
  return mkdtemp(tmpl);
}

// `chainsim <args>` run in dir
Result chainsim(const std::string& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir + "' && '" CHAINSIM_EXE "' " + args + " >out.txt 2>err.txt";
  const int st = std::system(cmd.c_str());
  Result r;
  r.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = read(dir + "/out.txt");
  r.err = read(dir + "/err.txt");
  return r;
}

std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream s(text);
  std::string l;
  while (std::getline(s, l))
    if (l.rfind(prefix, 0) == 0) out.push_back(l);
  return out;
}

struct Case {
  std::string name;
  double time = -1;
  std::map<std::string, std::string> props;
  std::vector<std::string> failures;  // message attributes
  std::string error;
};

std::vector<Case> junit_cases(const std::string& path, pt::ptree* doc) {
  std::ifstream in(path);
  pt::read_xml(in, *doc);
  std::vector<Case> out;
  for (const auto& s : doc->get_child("testsuites"))
    if (s.first == "testsuite")
      for (const auto& c : s.second) {
        if (c.first != "testcase") continue;
        Case k;
        k.name = c.second.get<std::string>("<xmlattr>.name");
        k.time = c.second.get<double>("<xmlattr>.time");
        // the run's details: "key: value" lines of its system-out, before the expectations
        std::istringstream sysout(c.second.get<std::string>("system-out"));
        for (std::string line; std::getline(sysout, line);) {
          const size_t colon = line.find(": ");
          if (line.rfind("pass  ", 0) == 0 || line.rfind("FAIL  ", 0) == 0 || colon == std::string::npos) continue;
          k.props[line.substr(0, colon)] = line.substr(colon + 2);
        }
        for (const auto& f : c.second) {
          if (f.first == "failure") k.failures.push_back(f.second.get<std::string>("<xmlattr>.message"));
          if (f.first == "error") k.error = f.second.get<std::string>("<xmlattr>.message");
        }
        out.push_back(k);
      }
  return out;
}

bool have_chromium() {
  if (const char* c = std::getenv("CHAINSIM_CHROMIUM"); c && *c) return access(c, X_OK) == 0;
  return access("/usr/bin/chromium", X_OK) == 0 || access("/usr/bin/chromium-browser", X_OK) == 0;
}

}  // namespace

TEST(TestCommand, PassingAndFailingFilesGiveLinesExitCodeAndJunit) {
  const std::string dir = temp_dir();
  const Result r = chainsim(dir, "test " TESTFILES "/pass.test.yaml " TESTFILES "/fail.test.yaml -j 2 --junit report.xml");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;  // an expectation failed

  // one line per test and seed, each expectation with its measured value
  const auto pass = lines_starting(r.out, "PASS  crawls seed 1");
  ASSERT_EQ(pass.size(), 1u) << r.out;
  EXPECT_NE(pass[0].find("no_faults: 0 faults"), std::string::npos) << pass[0];
  EXPECT_NE(pass[0].find("sim_time_s == 1: 1"), std::string::npos) << pass[0];
  EXPECT_NE(pass[0].find("bus i2c to 0x20 before 0.5: at 0.0"), std::string::npos) << pass[0];
  const auto fail = lines_starting(r.out, "FAIL  flies seed ");
  ASSERT_EQ(fail.size(), 2u) << r.out;
  for (const std::string& l : fail) {
    EXPECT_NE(l.find("chain.distance_m >= 5: 0.0"), std::string::npos) << l;
    EXPECT_NE(l.find(" FAILED | log m0 /flying/ before 0.5: never (run ended at 1 s) FAILED"), std::string::npos) << l;
  }

  // a real report (with failure pictures when Chromium is there) takes the
  // constraints both common JUnit schemas share (docs/testing.md)
  if (std::system("command -v xmllint >/dev/null 2>&1") == 0) {
    const std::string xsd = std::string(CHAINSIM_SOURCE_DIR) + "/tests/physics-server/testing/junit-common.xsd";
    EXPECT_EQ(std::system(("xmllint --noout --schema " + xsd + " " + dir + "/report.xml >" + dir + "/xmllint.txt 2>&1").c_str()), 0)
        << scenario::read_file(dir + "/xmllint.txt");
  }

  pt::ptree doc;
  const std::vector<Case> cases = junit_cases(dir + "/report.xml", &doc);
  EXPECT_EQ(doc.get<int>("testsuites.<xmlattr>.tests"), 3);
  EXPECT_EQ(doc.get<int>("testsuites.<xmlattr>.failures"), 2);
  EXPECT_EQ(doc.get<int>("testsuites.<xmlattr>.errors"), 0);
  ASSERT_EQ(cases.size(), 3u);
  std::map<std::string, const Case*> by_name;
  for (const Case& c : cases) by_name[c.name] = &c;
  ASSERT_TRUE(by_name.count("crawls seed 1") && by_name.count("flies seed 1") && by_name.count("flies seed 2"));
  const Case& ok = *by_name["crawls seed 1"];
  EXPECT_TRUE(ok.failures.empty());
  EXPECT_GT(ok.time, 0);
  EXPECT_EQ(ok.props.at("seed"), "1");
  EXPECT_EQ(ok.props.at("trace_sha256").size(), 64u);
  EXPECT_EQ(ok.props.count("run_dir"), 0u);  // a passed run is not kept without --keep
  for (const char* n : {"flies seed 1", "flies seed 2"}) {
    const Case& c = *by_name[n];
    ASSERT_EQ(c.failures.size(), 2u) << n;
    EXPECT_EQ(c.failures[0].rfind("chain.distance_m >= 5: measured 0.0", 0), 0u) << c.failures[0];
    EXPECT_EQ(c.failures[1], "log m0 /flying/ before 0.5: measured never (run ended at 1 s)");
    // the failed run is kept, with a replay and a picture at the failure time
    const std::string run = c.props.at("run_dir");
    EXPECT_TRUE(fs::exists(dir + "/" + run + "/summary.json")) << run;
    EXPECT_TRUE(fs::exists(dir + "/" + run + "/replay.html")) << run;
    EXPECT_EQ(c.props.at("failure_time_s"), "1.000");  // chain.distance_m is measured at the end
    if (have_chromium()) {
      EXPECT_TRUE(fs::exists(dir + "/" + run + "/failure-t1.000.png")) << run << "\n" << r.err;
      EXPECT_GT(fs::file_size(dir + "/" + run + "/failure-t1.000.png"), 1000u);
    }
  }
  EXPECT_NE(by_name["flies seed 1"]->props.at("trace_sha256"), by_name["flies seed 2"]->props.at("trace_sha256"));
  // each test is a normal run: chainsim run gives the same trace for the same scene and seed
  const Result run = chainsim(dir, "run " CHAINSIM_SOURCE_DIR "/scenes/default.yaml --duration 1 --out plain -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto summary = nlohmann::json::parse(read(dir + "/plain/summary.json"));
  EXPECT_EQ(summary["trace_sha256"].get<std::string>(), ok.props.at("trace_sha256"));
  fs::remove_all(dir);
}

TEST(TestCommand, SeedsAndKeep) {
  const std::string dir = temp_dir();
  const Result r = chainsim(dir, "test " TESTFILES "/pass.test.yaml --seeds 3..4 --keep kept --junit j.xml");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(lines_starting(r.out, "PASS  crawls seed ").size(), 2u) << r.out;
  // every run kept, each with the seed asked for
  for (int seed : {3, 4}) {
    const std::string s = dir + "/kept/crawls-seed" + std::to_string(seed) + "/summary.json";
    ASSERT_TRUE(fs::exists(s)) << r.out;
    EXPECT_EQ(nlohmann::json::parse(read(s))["seed"].get<int>(), seed);
  }
  pt::ptree doc;
  const auto cases = junit_cases(dir + "/j.xml", &doc);
  ASSERT_EQ(cases.size(), 2u);
  EXPECT_EQ(cases[0].props.at("run_dir"), "kept/crawls-seed3");
  EXPECT_EQ(chainsim(dir, "test " TESTFILES "/pass.test.yaml --seeds 5..4").exit_code, 2);
  fs::remove_all(dir);
}

// malformed: nothing runs, exit 2, the culprit named file:line:column
TEST(TestCommand, MalformedFilesAreNamedAndExitTwo) {
  const std::string dir = temp_dir();
  const std::string m = TESTFILES "/malformed/";
  struct Want {
    const char* file;
    const char* message;  // after "<file>:"
  } const wants[] = {
      {"unknown-key.test.yaml", "3:1: unknown key 'duraton_s' in 'test' (known: description, duration_s,"},
      {"bad-expectation.test.yaml",
       "5:28: expected final, max, min, mean, at T or a comparison after the column, got 'maximum'"},
      {"bad-override.test.yaml", "4:25: unknown key 'substep' in 'physics' (known: "},
      // a parameter the program does not declare, named at the test's key before anything runs
      {"misspelled-param.test.yaml",
       "5:13: parameter 'gaitt' of the central control: program fw-central declares no such parameter (did you "
       "mean 'gait'? "},
      // a program that is nowhere: named at the override that gives it
      {"cannot-start.test.yaml", "5:3: program 'fw-not-built-anywhere' of module 0 (rotation) not found"},
      // what RE2 has not, refused when the file is loaded, where it is written
      {"backreference.test.yaml",
       "6:22: unsupported pattern /(R)\\1/: '\\1' is a backreference: patterns are matched by RE2, in time linear "
       "in the line, without backreferences or lookaround"},
      {"lookahead.test.yaml", "6:23: unsupported pattern /chain(?= RRR)/: '(?=' is a lookahead: "},
  };
  for (const Want& w : wants) {
    const Result r = chainsim(dir, std::string("test ") + m + w.file + " --junit j.xml");
    EXPECT_EQ(r.exit_code, 2) << w.file << "\n" << r.out << r.err;
    EXPECT_NE(r.err.find(std::string("chainsim: ") + m + w.file + ":" + w.message), std::string::npos)
        << w.file << "\n" << r.err;
    EXPECT_NE(r.err.find("nothing was run"), std::string::npos) << r.err;
    pt::ptree doc;
    const auto cases = junit_cases(dir + "/j.xml", &doc);
    ASSERT_EQ(cases.size(), 1u);
    EXPECT_EQ(cases[0].error.rfind(m + w.file + ":" + w.message, 0), 0u) << cases[0].error;
  }
  // a column no run of the scene has: found once the run is there, still exit 2
  Result r = chainsim(dir, "test " + m + "unknown-column.test.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("ERROR unknown column seed 1: " + m +
                       "unknown-column.test.yaml:5:6: unknown trace column 'm0.s0.currant_a' (columns of m0: "),
            std::string::npos) << r.out;
  // command-line mistakes are exit 2 too (1 means an expectation failed)
  EXPECT_EQ(chainsim(dir, "test --no-such-option " + m).exit_code, 2);
  r = chainsim(dir, "test /no/such/file.test.yaml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/no/such/file.test.yaml: no such test file or folder"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// Patterns with nested quantifiers over lines of 80 'a' and a 'b', which a
// backtracking engine (std::regex was used before) never finishes: RE2 takes
// one pass per line. What guards the test is its ctest TIMEOUT, not a clock
// here: the run completes, with the right verdict for each pattern.
TEST(TestCommand, NestedQuantifiersOverLongLinesGiveTheirVerdict) {
  const std::string dir = temp_dir();
  const Result r = chainsim(dir, "test " TESTFILES "/catastrophic-pattern.test.yaml --firmware-dir " TEST_FIRMWARE_DIR
                                 " --junit j.xml");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto pass = lines_starting(r.out, "PASS  catastrophic pattern seed ");
  ASSERT_EQ(pass.size(), 1u) << r.out << r.err;
  EXPECT_NE(pass[0].find("| log m0 /^(a+)+$/ count == 1: 1 |"), std::string::npos) << pass[0];
  EXPECT_NE(pass[0].find("| log m0 /(a|aa)+c/ never: never"), std::string::npos) << pass[0];
  EXPECT_NE(pass[0].find("| log m0 /^(a+)+b$/ before 0.1: at 0.0"), std::string::npos) << pass[0];
  pt::ptree doc;
  const auto cases = junit_cases(dir + "/j.xml", &doc);
  ASSERT_EQ(cases.size(), 1u);
  EXPECT_TRUE(cases[0].failures.empty());
  fs::remove_all(dir);
}

namespace {

// `chainsim test <args>` started in dir (stdout and stderr to files there)
pid_t start_test_command(const std::string& dir, const std::vector<std::string>& args) {
  std::vector<std::string> all{CHAINSIM_EXE, "test"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(127);
    dup2(open("out.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644), 1);
    dup2(open("err.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644), 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

// the exit code of pid (-1: a signal, or still running after timeout_s, then killed)
int exit_code_within(pid_t pid, double timeout_s) {
  int st = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (waitpid(pid, &st, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

}  // namespace

// Ctrl-C (SIGINT) or a SIGTERM to chainsim test alone while a run goes on:
// the run is ended at once and keeps what it wrote, chainsim test exits 130,
// and no process of it is left (the run's server and its module processes
// are found by their environment: TMPDIR is this test's directory)
TEST(TestCommand, InterruptedDuringARunEndsWith130AndLeavesNoProcess) {
  for (const int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(strsignal(sig));
    const std::string dir = temp_dir();
    const scenario::TmpDirForChildren tmp(dir);
    const pid_t pid = start_test_command(
        dir, {TESTFILES "/long-run.test.yaml", "--firmware-dir", TEST_FIRMWARE_DIR, "--keep", "kept"});
    // the run is going: its module process is there
    const bool going = scenario::wait_until(
        [&] {
          for (const pid_t p : scenario::processes_with_env("TMPDIR=" + dir))
            if (scenario::read_file("/proc/" + std::to_string(p) + "/environ").find("CHAINSIM_MODULE_INDEX=0") !=
                std::string::npos)
              return true;
          return false;
        },
        60);
    ASSERT_TRUE(going) << scenario::read_file(dir + "/err.txt");
    kill(pid, sig);
    const int code = exit_code_within(pid, 60);
    const std::string out = scenario::read_file(dir + "/out.txt");
    EXPECT_EQ(code, 130) << out << scenario::read_file(dir + "/err.txt");
    EXPECT_NE(out.find("INTR  long run seed 1: interrupted"), std::string::npos) << out;
    EXPECT_NE(out.find("chainsim test: 0 passed, 0 failed, 1 errors"), std::string::npos) << out;
    // the run ended as an interrupted chainsim run does: its summary says so
    const auto summary = nlohmann::json::parse(scenario::read_file(dir + "/kept/long_run-seed1/summary.json"),
                                               nullptr, false);
    ASSERT_TRUE(summary.is_object()) << out;
    EXPECT_EQ(summary.value("exit_code", -1), 130);
    EXPECT_LT(summary.value("sim_time_s", 600.0), 600.0);
    // nothing is left: the run's server, its module and its central control
    // ended before chainsim test did
    EXPECT_EQ(scenario::processes_with_env("TMPDIR=" + dir).size(), 0u);
    fs::remove_all(dir);
  }
}
