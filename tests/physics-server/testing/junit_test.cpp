// The JUnit report parses as XML and holds, for each test and seed, its
// failures (expectation and measured value), time and properties.
#include <gtest/gtest.h>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <sstream>

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
  std::map<std::string, std::string> props;
  for (const auto& p : c0.get_child("properties"))
    props[p.second.get<std::string>("<xmlattr>.name")] = p.second.get<std::string>("<xmlattr>.value");
  EXPECT_EQ(props["seed"], "3");
  EXPECT_EQ(props["trace_sha256"], "abc123");
  EXPECT_EQ(props["run_dir"], "runs/t/crawl-seed3");
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

TEST(Junit, ControlCharactersDoNotBreakTheXml) {
  EXPECT_EQ(xml_escape("a\x01<b>\n"), "a&lt;b&gt;&#10;");
}
