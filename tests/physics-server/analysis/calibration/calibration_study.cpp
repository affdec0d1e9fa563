// Many-seed study of `chainsim calibrate` on the synthetic cases (synth.h):
// confusion table (true case -> verdict / effects found), the false-positive
// rate on null data, the median gap shrink. Not a ctest (minutes):
//   build/bin/calibration_study [--seeds N] [--first S]
#include <cstdio>
#include <cstring>
#include <map>

#include "common.h"

int main(int argc, char** argv) {
  int seeds = 20, first = 100;
  for (int i = 1; i + 1 < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds")) seeds = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--first")) first = std::atoi(argv[i + 1]);
  }
  const auto cases = synth::cases();
  const std::string dir = synth::make_temp_dir();
  std::printf("| hidden | runs | exactly right | verdict as expected | top effect right | median gap before -> after | outcomes |\n|---|---|---|---|---|---|---|\n");
  int fp = 0, null_runs = 0;
  for (const auto& c : cases) {
    int exact = 0, verdict_ok = 0, top_ok = 0;
    std::map<std::string, int> outcomes;
    std::vector<double> gb, ga;
    for (int s = 0; s < seeds; ++s) {
      const synth::Outcome o = synth::calibrate_case(c, first + s, dir);
      if (o.exit_code != 0 || !o.report.is_object()) {
        ++outcomes["error"];
        continue;
      }
      std::vector<std::string> names;
      for (const auto& e : o.report["effects"]) names.push_back(e["name"]);
      std::string key = o.report["verdict"].get<std::string>();
      for (const auto& n : names) key += " " + n;
      ++outcomes[key];
      std::vector<std::string> a = names, b = c.expect;
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      const bool v = o.report["verdict"] == c.verdict;
      verdict_ok += v;
      exact += v && a == b;
      top_ok += c.expect.empty() ? names.empty() : (!names.empty() && std::find(b.begin(), b.end(), names[0]) != b.end());
      gb.push_back(o.report["gap_before"]);
      ga.push_back(o.report["gap_after"]);
      if (c.name == "null") {
        ++null_runs;
        fp += !names.empty();
      }
      std::fprintf(stderr, "%s seed %d: %s\n", c.name.c_str(), first + s, key.c_str());
    }
    std::sort(gb.begin(), gb.end());
    std::sort(ga.begin(), ga.end());
    std::string oc;
    for (const auto& [k, n] : outcomes) oc += (oc.empty() ? "" : "; ") + k + ": " + std::to_string(n);
    std::printf("| %s | %d | %d | %d | %d | %.3f -> %.3f | %s |\n", c.name.c_str(), seeds, exact, verdict_ok, top_ok,
                gb.empty() ? 0 : gb[gb.size() / 2], ga.empty() ? 0 : ga[ga.size() / 2], oc.c_str());
    std::fflush(stdout);
  }
  std::printf("\nfalse positives on null data (any effect added): %d of %d\n", fp, null_runs);
  std::system(("rm -rf '" + dir + "'").c_str());
  return 0;
}
