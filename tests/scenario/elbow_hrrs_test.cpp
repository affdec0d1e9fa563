// Paper 6.6 (rotation + helicoidal + support): H R R S in the 80 mm elbow
// of the other elbow scenes (scenes/elbow-HRRS.yaml). The helicoidal module
// leads; it stalls at the elbow's entry as it does alone; the central
// control takes its stall current for the elbow, bends both rotation modules
// 70 degrees toward the given turn, which drags the chain into the bend and
// brings the H to the bend's end, and after 3 s lets them go limp: the H
// drives out and pulls the rest through. Controls: without the steering the
// H stays at the entry; with the paper's sequence (the support gripping the
// wall while the rotation modules turn) the grip holds the chain back and
// the H stays at the entry; straightening instead of going limp leaves the
// H at the bend's end when the solver converges. docs/firmware.md, "A
// helicoidal module placed by the rotation modules (paper 6.6)".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "scenario_util.h"

using namespace scenario;

namespace {

// the pipe: the entry leg along +x to x = 0.55, the elbow (bend radius
// 0.08 m) to the left, the outgoing leg at x = 0.63 from y = 0.08 on
constexpr double kElbowX = 0.55, kRadius = 0.08;
constexpr double kHalfH = 0.023;  // the helicoidal module's pig: 46 mm long, centred

using Trace = std::map<std::string, std::vector<double>>;

struct Where {
  double x, y;
};

// where a body ends up (the last trace row)
Where last(const Trace& tr, const std::string& body) { return {tr.at(body + ".x").back(), tr.at(body + ".y").back()}; }

// the first time the H's back end is 2 cm into the outgoing leg, -1 if never
double time_out(const Trace& tr) {
  const auto &t = tr.at("t_s"), &x = tr.at("m0.pig.x"), &y = tr.at("m0.pig.y");
  for (size_t i = 0; i < t.size(); ++i)
    if (y[i] - kHalfH > kRadius + 0.02 && std::fabs(x[i] - (kElbowX + kRadius)) < 0.01) return t[i];
  return -1;
}

// the time (s) of the central control's first "elbow: <what> at ms N" line, -1 if none
double log_time(const std::string& log, const std::string& what) {
  const std::vector<double> t = log_times(log, "elbow: " + what);
  return t.empty() ? -1.0 : t[0];
}

}  // namespace

// The verdict, under QuickStep (the scene) and with the solver converged:
// the H is wholly in the outgoing leg (its back end 2 cm past the bend's
// end) within 10 s and ends 10 cm and more into it at 14 s, and the tail
// (the support module's back cylinder) is past the bend's end.
TEST(Elbow, HRRSGetsItsHelicoidalModuleThroughThe80mmElbow) {
  for (const bool exact : {false, true}) {
    SCOPED_TRACE(exact ? "exact" : "QuickStep");
    std::vector<std::pair<std::string, std::string>> edits;
    if (exact) edits.push_back(kExactSolver);
    const Outcome o = run_scene("elbow-hrrs", "elbow-HRRS", 14, edits);
    ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
    const std::string log = central_log(o, 4);
    // the stall is taken for the elbow once, the bend is the given turn, and
    // the rotation modules go limp 3 s later; the support never grips
    const double stall = log_time(log, "stall"), limp = log_time(log, "limp");
    EXPECT_GT(stall, 3.0) << log;  // the H reaches the elbow at about 3 s, 5 cm from the start
    EXPECT_NE(log.find("elbow: bend at ms " + std::to_string(std::lround(stall * 1e3)) + " toward dir_deg=90 (given)"),
              std::string::npos) << log;
    EXPECT_NEAR(limp - stall, 3.0, 1e-6) << log;
    EXPECT_EQ(log.find("elbow: hold"), std::string::npos) << log;
    const Trace tr = read_trace(o.dir + "/trace.csv");
    const Where h = last(tr, "m0.pig"), tail = last(tr, "m3.back");
    const double t_out = time_out(tr);
    std::printf("[ elbow ] H R R S%s: stall at %.2f s, H out at %.2f s, H at (%.3f, %.3f), tail at (%.3f, %.3f)\n",
                exact ? ", exact" : "", stall, t_out, h.x, h.y, tail.x, tail.y);
    EXPECT_GT(t_out, limp) << "the H got out before the rotation modules let go";
    EXPECT_LT(t_out, 10.0);
    EXPECT_NEAR(h.x, kElbowX + kRadius, 0.01);  // in the outgoing leg
    EXPECT_GT(h.y - kHalfH, kRadius + 0.10);    // its back end 10 cm into it
    EXPECT_GT(tail.y, kRadius);                 // the support module past the bend's end
  }
}

// Controls, with the solver converged (the exact solver): the same chain and
// pipe with no steering (the H stalls at the entry, as it does alone); with
// the support gripping the wall from the bend for 3 s (the paper's
// sequence: the rotation modules cannot bend and the chain does not move;
// then the H stays at the entry, creeping); and straightening instead of going limp
// (the H ends at the bend's end, its stator wheels still in the bend, at
// stall current).
TEST(Elbow, HRRSNeedsTheBendAndTheLimpRotationModulesAndNoGrip) {
  struct Case {
    const char* name;
    std::pair<std::string, std::string> edit;
  };
  for (const Case& k : {Case{"no steering", {"elbow_dir_deg: 90 ", "elbow_dir_deg: -2 "}},
                        Case{"support holding", {"hold_ms: 0 ", "hold_ms: 3000 "}},
                        Case{"straightening", {"bend_limp: 1", "bend_limp: 0"}}}) {
    SCOPED_TRACE(k.name);
    const std::string name = k.name;
    const Outcome o = run_scene("elbow-hrrs", "elbow-HRRS", 14, {kExactSolver, k.edit});
    ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
    const std::string log = central_log(o, 4);
    const Trace tr = read_trace(o.dir + "/trace.csv");
    const Where h = last(tr, "m0.pig");
    // the H's current, mean over the last 2 s: it pushes at the elbow at its
    // stall current (5 V / 12 ohm; asked 0.95 of it); after the support's
    // grip it creeps in spurts at the entry as its wheels slip (2 cm in the
    // last 6 s), measured 0.90-0.91 of it, asked 0.85 (the last sample alone
    // falls anywhere in a spurt)
    const auto& t = tr.at("t_s");
    const auto& i_h = tr.at("m0.s0.current_a");
    double sum = 0;
    int n = 0;
    for (size_t j = 0; j < t.size(); ++j)
      if (t[j] >= t.back() - 2.0) sum += i_h[j], ++n;
    ASSERT_GT(n, 0);
    const double current = sum / n;
    std::printf("[ elbow ] H R R S, exact, %s: H at (%.3f, %.3f), %.3f A (mean of the last 2 s)\n", k.name, h.x, h.y,
                current);
    EXPECT_LT(time_out(tr), 0);
    EXPECT_GT(current, (name == "support holding" ? 0.85 : 0.95) * 5.0 / 12.0);  // stalled (creeping)
    if (name == "straightening") {
      EXPECT_GT(h.y, kRadius - 0.01);  // at the bend's end, not out
      EXPECT_LT(h.y - kHalfH, kRadius);
    } else {
      EXPECT_GT(h.x, kElbowX);  // at the entry
      EXPECT_LT(h.x, 0.60);
      EXPECT_LT(h.y, 0.02);
    }
    if (name == "no steering") {
      EXPECT_EQ(log.find("elbow: bend"), std::string::npos) << log;
    }
    if (name == "support holding") {
      // while the support grips, the rotation modules get less than half of
      // the 70 degrees commanded and the chain does not move
      const double from = log_time(log, "hold"), to = log_time(log, "release");
      ASSERT_GT(from, 0) << log;
      EXPECT_NEAR(to - from, 3.0, 1e-6) << log;
      double bent = 0, x0 = -1, x1 = 0;
      for (size_t i = 0; i < t.size(); ++i) {
        if (t[i] < from + 0.5 || t[i] > to) continue;  // (the arms take a few tenths of a second to grip)
        for (const char* yaw : {"m1.s1.angle_deg", "m2.s1.angle_deg"}) bent = std::max(bent, -tr.at(yaw)[i]);
        if (x0 < 0) x0 = tr.at("m0.pig.x")[i];
        x1 = tr.at("m0.pig.x")[i];
      }
      std::printf("[ elbow ]   while the support holds: rotation modules' yaw at most %.1f deg, the H moved %.1f mm\n",
                  bent, (x1 - x0) * 1e3);
      EXPECT_LT(bent, 30.0);
      EXPECT_LT(std::fabs(x1 - x0), 0.002);
    }
  }
}
