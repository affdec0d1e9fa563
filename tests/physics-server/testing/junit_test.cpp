// The JUnit report parses as XML and holds, for each test and seed, its
// failures (expectation and measured value), time and properties.
#include <gtest/gtest.h>

#include <unistd.h>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "testing/junit.h"

using namespace chainsim;
namespace pt = boost::property_tree;

TEST(Junit, OneTestcasePerTestAndSeedWithFailuresAndProperties) {
  TestCaseResult a;
  a.file = "tests/a.test.yaml";
  a.name = "crawl <fast> & \"far\"";
  a.seed = 3;
  a.status = TestCaseResult::Status::failed;
  a.wall_s = 1.25;
  a.trace_sha256 = "abc123";
  a.run_dir = "runs/t/crawl-seed3";
  CheckResult pass;
  pass.pass = true;
  pass.measured = "0 faults";
  CheckResult fail;
  fail.measured = "0.153";
  a.checks = {{"no_faults", "tests/a.test.yaml:5:5", pass},
              {"chain.distance_m >= 0.2", "tests/a.test.yaml:6:6", fail}};
  TestCaseResult b = a;
  b.seed = 4;
  b.status = TestCaseResult::Status::passed;
  b.checks[1].result.pass = true;
  TestCaseResult c;
  c.file = "tests/b.test.yaml";
  c.name = "broken";
  c.status = TestCaseResult::Status::error;
  c.error = "tests/b.test.yaml:3:1: unknown key 'x'";

  std::istringstream in(junit_xml({a, b, c}, 9.5));
  pt::ptree doc;
  pt::read_xml(in, doc);
  const pt::ptree& suites = doc.get_child("testsuites");
  EXPECT_EQ(suites.get<int>("<xmlattr>.tests"), 3);
  EXPECT_EQ(suites.get<int>("<xmlattr>.failures"), 1);
  EXPECT_EQ(suites.get<int>("<xmlattr>.errors"), 1);
  std::vector<const pt::ptree*> cases;
  int nsuites = 0;
  for (const auto& s : suites)
    if (s.first == "testsuite") {
      ++nsuites;
      for (const auto& c2 : s.second)
        if (c2.first == "testcase") cases.push_back(&c2.second);
    }
  EXPECT_EQ(nsuites, 2);  // one per file
  ASSERT_EQ(cases.size(), 3u);
  const pt::ptree& c0 = *cases[0];
  EXPECT_EQ(c0.get<std::string>("<xmlattr>.name"), "crawl <fast> & \"far\" seed 3");
  EXPECT_DOUBLE_EQ(c0.get<double>("<xmlattr>.time"), 1.25);
  // no attribute or element the common schemas refuse in a testcase
  EXPECT_EQ(c0.count("properties"), 0u);
  EXPECT_FALSE(c0.get_optional<std::string>("<xmlattr>.file"));
  const std::string out = c0.get<std::string>("system-out");
  EXPECT_NE(out.find("file: tests/a.test.yaml\nseed: 3\ntrace_sha256: abc123\nrun_dir: runs/t/crawl-seed3\n"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("FAIL  chain.distance_m >= 0.2: 0.153\n"), std::string::npos) << out;
  int failures = 0;
  for (const auto& f : c0)
    if (f.first == "failure") {
      ++failures;
      EXPECT_EQ(f.second.get<std::string>("<xmlattr>.message"), "chain.distance_m >= 0.2: measured 0.153");
      EXPECT_NE(f.second.data().find("tests/a.test.yaml:6:6"), std::string::npos) << f.second.data();
    }
  EXPECT_EQ(failures, 1);
  EXPECT_EQ(cases[1]->count("failure"), 0u);
  EXPECT_EQ(cases[2]->get<std::string>("error.<xmlattr>.message"), "tests/b.test.yaml:3:1: unknown key 'x'");
}

// the report validates against the constraints both common JUnit schemas
// share (junit-common.xsd, beside this test: the Jenkins xunit plugin's
// junit-10.xsd and junit5's jenkins-junit.xsd), for passed, failed, errored
// and interrupted cases, with artefacts
TEST(Junit, TheReportValidatesAgainstTheSchemasCiServersUse) {
  if (std::system("command -v xmllint >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "xmllint (Debian libxml2-utils, installed by tools/setup.sh) is not installed";
  TestCaseResult a;
  a.file = "tests/a.test.yaml";
  a.name = "crawl";
  a.seed = 1;
  a.status = TestCaseResult::Status::failed;
  a.wall_s = 2;
  a.trace_sha256 = "abc";
  a.run_dir = "runs/x";
  a.failure_t_s = 1;
  a.artefacts = {"runs/x/replay.html", "runs/x/failure.png"};
  CheckResult fail;
  fail.measured = "0.1";
  a.checks = {{"chain.distance_m >= 1", "tests/a.test.yaml:5:5", fail}};
  TestCaseResult b = a;
  b.status = TestCaseResult::Status::passed;
  b.checks[0].result.pass = true;
  b.artefacts.clear();
  TestCaseResult c;
  c.file = "tests/b.test.yaml";
  c.name = "broken";
  c.status = TestCaseResult::Status::error;
  c.error = "tests/b.test.yaml:3:1: unknown key 'x'";
  TestCaseResult d = c;
  d.status = TestCaseResult::Status::interrupted;
  d.error.clear();
  const std::string xml = testing::TempDir() + "/junit_schema_test_" + std::to_string(getpid()) + ".xml";
  const std::string xsd = std::string(CHAINSIM_SOURCE_DIR) + "/tests/physics-server/testing/junit-common.xsd";
  const std::string log = xml + ".log";
  std::ofstream(xml) << junit_xml({a, b, c, d}, 12345.5);
  EXPECT_EQ(std::system(("xmllint --noout --schema " + xsd + " " + xml + " >" + log + " 2>&1").c_str()), 0)
      << std::ifstream(log).rdbuf();
  // and the schema is no formality: the attribute and element both schemas refused before are refused
  std::string old_style = junit_xml({a}, 1);
  old_style.replace(old_style.find(" time=\"2.000\""), 0, " file=\"tests/a.test.yaml\"");
  std::ofstream(xml) << old_style;
  EXPECT_NE(std::system(("xmllint --noout --schema " + xsd + " " + xml + " >" + log + " 2>&1").c_str()), 0);
  std::ifstream l(log);
  const std::string said((std::istreambuf_iterator<char>(l)), std::istreambuf_iterator<char>());
  EXPECT_NE(said.find("The attribute 'file' is not allowed"), std::string::npos) << said;
}

TEST(Junit, ControlCharactersDoNotBreakTheXml) {
  EXPECT_EQ(xml_escape("a\x01<b>\n"), "a&lt;b&gt;&#10;");
}
