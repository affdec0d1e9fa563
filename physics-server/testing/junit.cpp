#include "testing/junit.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace chainsim {
namespace {

std::string seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", s);
  return b;
}

// one testcase. Only what both common schemas allow (the Jenkins xunit
// plugin's junit-10.xsd and junit5's jenkins-junit.xsd): name, classname and
// time on the testcase, and no properties in it; the run's details (seed,
// trace fingerprint, run directory, artefacts) go to its system-out, where
// GitLab shows them with a failure and reads [[ATTACHMENT|path]] as a picture
void testcase(std::ostringstream& x, const TestCaseResult& r) {
  x << "    <testcase classname=\"" << xml_escape(r.name) << "\" name=\"" << xml_escape(r.name) << " seed "
    << r.seed << "\" time=\"" << seconds(r.wall_s) << "\">\n";
  if (r.status == TestCaseResult::Status::error || r.status == TestCaseResult::Status::interrupted) {
    const std::string msg = r.error.empty() ? "interrupted" : r.error;
    x << "      <error message=\"" << xml_escape(msg) << "\" type=\"error\">" << xml_escape(msg) << "</error>\n";
  }
  for (const CheckOutcome& c : r.checks) {
    if (c.result.pass) continue;
    const std::string msg = c.expectation + ": measured " + c.result.measured;
    x << "      <failure message=\"" << xml_escape(msg) << "\" type=\"expectation\">"
      << xml_escape(c.where + ": expected " + c.expectation + "\nmeasured " + c.result.measured) << "</failure>\n";
  }
  std::string out = "file: " + r.file + "\nseed: " + std::to_string(r.seed) + "\n";
  if (!r.trace_sha256.empty()) out += "trace_sha256: " + r.trace_sha256 + "\n";
  if (!r.run_dir.empty()) out += "run_dir: " + r.run_dir + "\n";
  if (r.failure_t_s >= 0) out += "failure_time_s: " + seconds(r.failure_t_s) + "\n";
  for (const std::string& a : r.artefacts) {
    out += "artefact: " + a + "\n";
    if (a.size() > 4 && a.ends_with(".png")) out += "[[ATTACHMENT|" + a + "]]\n";
  }
  for (const CheckOutcome& c : r.checks)
    out += std::string(c.result.pass ? "pass" : "FAIL") + "  " + c.expectation + ": " + c.result.measured + "\n";
  x << "      <system-out>" << xml_escape(out) << "</system-out>\n";
  x << "    </testcase>\n";
}

}  // namespace

std::string xml_escape(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (unsigned char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&apos;"; break;
      case '\n': o += "&#10;"; break;
      case '\t': o += "&#9;"; break;
      default:
        if (c >= 0x20) o += static_cast<char>(c);  // XML 1.0 has no other control characters
    }
  }
  return o;
}

std::string junit_xml(const std::vector<TestCaseResult>& results, double wall_s) {
  // one suite per file, in the order the files came
  std::vector<std::string> files;
  std::map<std::string, std::vector<const TestCaseResult*>> by_file;
  for (const auto& r : results) {
    if (!by_file.count(r.file)) files.push_back(r.file);
    by_file[r.file].push_back(&r);
  }
  auto count = [](const std::vector<const TestCaseResult*>& v, TestCaseResult::Status s) {
    int n = 0;
    for (const auto* r : v) n += r->status == s;
    return n;
  };
  std::vector<const TestCaseResult*> all;
  for (const auto& r : results) all.push_back(&r);
  const auto errors = [&](const std::vector<const TestCaseResult*>& v) {
    return count(v, TestCaseResult::Status::error) + count(v, TestCaseResult::Status::interrupted);
  };
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x << "<testsuites name=\"chainsim test\" tests=\"" << all.size() << "\" failures=\""
    << count(all, TestCaseResult::Status::failed) << "\" errors=\"" << errors(all) << "\" time=\"" << seconds(wall_s)
    << "\">\n";
  for (const std::string& f : files) {
    const auto& v = by_file[f];
    double t = 0;
    for (const auto* r : v) t += r->wall_s;
    x << "  <testsuite name=\"" << xml_escape(f) << "\" tests=\"" << v.size() << "\" failures=\""
      << count(v, TestCaseResult::Status::failed) << "\" errors=\"" << errors(v) << "\" skipped=\"0\" time=\""
      << seconds(t) << "\">\n";
    for (const auto* r : v) testcase(x, *r);
    x << "  </testsuite>\n";
  }
  x << "</testsuites>\n";
  return x.str();
}

bool write_junit(const std::string& path, const std::vector<TestCaseResult>& results, double wall_s) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << junit_xml(results, wall_s);
    if (!f.flush()) return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  return !ec;
}

}  // namespace chainsim
