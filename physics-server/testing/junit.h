// JUnit XML for CI systems (GitHub Actions, GitLab CI, Jenkins): one
// <testsuite> per test file, one <testcase> per test and seed, one <failure>
// per failed expectation (the expectation, where it is written and what was
// measured), an <error> for a malformed file or a run that could not start,
// and properties seed, trace_sha256 and run_dir.
#pragma once

#include <string>
#include <vector>

#include "testing/test_result.h"

namespace chainsim {

// the report as text
std::string junit_xml(const std::vector<TestCaseResult>& results, double wall_s);

// writes it to path (via a temporary file); false when it cannot be written
bool write_junit(const std::string& path, const std::vector<TestCaseResult>& results, double wall_s);

// text for XML (attribute or element): & < > " ' escaped, control characters dropped
std::string xml_escape(const std::string& s);

}  // namespace chainsim
