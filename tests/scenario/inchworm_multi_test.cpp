// S E S E S E S (gait 8, scenes/inchworm-multi.yaml, level, 500 ms steps,
// the fitted 0.356 N extension), paper 6.5: with rigid docks it all but
// stalls, each extension stopping a couple of millimetres into its 15 mm
// stroke; with the male/female connectors' play (physics.dock.play_deg,
// docs/scene-reference.md) it moves at most of the gait's ideal speed,
// stroke / (n_supports x step) = 0.75 cm/s. Gait 13 (every extension at
// once, the paper's "more speed"): S E S E S beats S E S; S E S E S E S
// does not with the fitted extension, whose force the drag of the released
// chain nearly uses up, and does with twice that force. Measured, both
// solvers: docs/notes/2026-11-29-inchworm-multi-forces.md.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "scenario_util.h"

using namespace scenario;

namespace {

using Trace = std::map<std::string, std::vector<double>>;

// the exact solver and the docks as joints with play_deg of play
std::pair<std::string, std::string> exact_with_docks(const std::string& play_deg) {
  return {"tick_us: 1000", "tick_us: 1000\n  solver: exact\n  dock: {play_deg: " + play_deg + "}"};
}

// the head support's speed along the level pipe (+x) from from_s to the end, cm/s
double multi_head_speed_cm_s(const Trace& tr, double from_s) {
  const std::vector<double>& t = tr.at("t_s");
  const std::vector<double>& x = tr.at("m0.front.x");
  size_t i = 0;
  while (i + 1 < t.size() && t[i] < from_s) ++i;
  return (x.back() - x[i]) / (t.back() - t[i]) * 100;
}

}  // namespace

// Rigid docks (joints with no play, so their forces are measured): while
// the head support is released and extension 0 pushes it, the extension
// pushes its whole stall force into the gripping support behind it (dock 1)
// and the slider stops short; only a fraction of that force reaches the
// head support (dock 0): the rest goes into the wall, where the extension's
// front box is held against it by a slider axis that the gripping support
// behind, rigidly docked, holds tilted.
TEST(InchwormMulti, RigidDocksWedgeTheExtensionAgainstTheWall) {
  const Outcome o = run_scene("iwm-rigid", "inchworm-multi", 4, {exact_with_docks("0")});
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  const Trace tr = read_trace(o.dir + "/trace.csv");
  const double v = multi_head_speed_cm_s(tr, 2.0);
  // the pushes of extension 0 (set-point out, head support released)
  // after the first cycle, once the slider has had 150 ms to move
  const std::vector<double>& t = tr.at("t_s");
  double pushed = 0, reached = 0, worst_mm = 0;
  int n = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] < 2.0 || tr.at("m1.s0.setpoint_mm")[i] < 10 || tr.at("m0.s0.setpoint_deg")[i] > 45) continue;
    if (i < 15 || tr.at("m1.s0.setpoint_mm")[i - 15] < 10) continue;  // 150 ms into the stroke
    pushed += -tr.at("dock1.axial_N")[i];
    reached += -tr.at("dock0.axial_N")[i];
    worst_mm = std::max(worst_mm, tr.at("m1.s0.position_mm")[i]);
    ++n;
  }
  ASSERT_GT(n, 5);
  pushed /= n;
  reached /= n;
  std::printf("[ inchworm-multi ] rigid docks: head %.3f cm/s; extension 0 pushes %.3f N into the support behind, "
              "%.3f N reach the head support, its slider at most %.2f mm out\n",
              v, pushed, reached, worst_mm);
  EXPECT_LT(v, 0.25);              // measured 0.08 over 2-4 s and 1-10 s (ideal 0.75)
  EXPECT_GT(pushed, 0.9 * 0.356);  // the extension stalls at its full force...
  EXPECT_LT(reached, 0.5 * pushed);  // ...and most of it never reaches the head support
  EXPECT_LT(worst_mm, 5.0);        // of a 15 mm stroke
}

// The same chain with the docks' play (1 degree each way, the estimate of
// docs/scene-reference.md): it moves at most of its gait's ideal speed,
// still half of S E S's (the gait moves one support at a time).
TEST(InchwormMulti, DockPlayFreesTheLongChain) {
  const Outcome o = run_scene("iwm-play", "inchworm-multi", 4, {exact_with_docks("1")});
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  const double v = multi_head_speed_cm_s(read_trace(o.dir + "/trace.csv"), 2.0);
  std::printf("[ inchworm-multi ] docks with 1 degree of play: head %.3f cm/s (ideal 0.75)\n", v);
  EXPECT_GT(v, 0.45);  // measured 0.67 over 2-4 s (0.61 over 1-10 s: the first cycles are slower)
  EXPECT_LT(v, 0.78);
}

namespace {

// inchworm-multi.yaml as `chain` under gait 13 (the exact solver, the docks
// as rigid joints so that their forces are in the trace), the pipe long
// enough for 4.5 cm/s; extra_edits on top
Outcome run_gait13(const std::string& tag, const std::string& chain,
                   std::vector<std::pair<std::string, std::string>> extra_edits = {}) {
  std::vector<std::pair<std::string, std::string>> e = {
      exact_with_docks("0"), {"chain: SESESES", "chain: " + chain}, {"gait: 8", "gait: 8\n    inchworm_all: 1"},
      {"length_m: 0.6", "length_m: 1.0"}};
  e.insert(e.end(), extra_edits.begin(), extra_edits.end());
  return run_scene(tag, "inchworm-multi", 4, e);
}

// mean axial force (N, + = tension) across dock d over the middle halves of
// gait 13's pushes (the first of the two 500 ms steps) after 2 s
double mean_push_axial(const Trace& tr, int d) {
  const std::vector<double>& t = tr.at("t_s");
  const std::vector<double>& f = tr.at("dock" + std::to_string(d) + ".axial_N");
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    const double in_cycle = t[i] - 1.0 * static_cast<int>(t[i] / 1.0 + 1e-9);
    if (t[i] < 2.0 || in_cycle < 0.125 || in_cycle >= 0.375) continue;
    sum += f[i];
    ++n;
  }
  return n ? sum / n : 0;
}

}  // namespace

// Gait 13 adds the extensions' strokes: S E S E S (ideal 3.0 cm/s at
// 500 ms steps) goes faster than S E S (1.5), with the solver converged.
TEST(InchwormMulti, AllExtensionsAtOnceMakeTheLongerChainFaster) {
  const Outcome ses = run_gait13("iwm13-ses", "SES");
  const Outcome seses = run_gait13("iwm13-seses", "SESES");
  ASSERT_EQ(ses.exit_code, 0) << ses.stderr_text;
  ASSERT_EQ(seses.exit_code, 0) << seses.stderr_text;
  const double v3 = multi_head_speed_cm_s(read_trace(ses.dir + "/trace.csv"), 2.0);
  const double v5 = multi_head_speed_cm_s(read_trace(seses.dir + "/trace.csv"), 2.0);
  std::printf("[ inchworm-multi ] gait 13: S E S %.3f, S E S E S %.3f cm/s\n", v3, v5);
  EXPECT_GT(v3, 1.2);        // measured 1.43 over 1-10 s (ideal 1.5: gait 13 is gait 8 with two supports)
  EXPECT_GT(v5, 1.3 * v3);   // measured 2.19 over 1-10 s (ideal 3.0)
}

// S E S E S E S under gait 13 with the fitted 0.356 N extension: the
// extension behind the moving chain drags all of it (its weight times mu on
// the wall, nearly all carried by the extensions' boxes) and runs near its
// stall force, so the chain is no faster than S E S. Twice the force (the
// same module file, fmax_n 0.712 N) takes it to most of its ideal 4.5 cm/s.
TEST(InchwormMulti, TheLongestChainIsBoundByTheExtensionsForce) {
  const Outcome fitted = run_gait13("iwm13-7", "SESESES");
  ASSERT_EQ(fitted.exit_code, 0) << fitted.stderr_text;
  const Trace tr = read_trace(fitted.dir + "/trace.csv");
  const double v = multi_head_speed_cm_s(tr, 2.0);
  // the force ahead of the rear extension (dock 4: S2 | E2) in the push:
  // what the released chain ahead drags
  const double drag = -mean_push_axial(tr, 4);

  std::string ext = read_file(scene_path("modules/extension"));
  const size_t at = ext.find("fmax_n: 0.356");
  ASSERT_NE(at, std::string::npos);
  ext.replace(at, 13, "fmax_n: 0.712");
  const std::string file = write_file(temp_dir("iwm13-ext"), "extension.yaml", ext);
  const Outcome strong = run_gait13("iwm13-7-strong", "SESESES", {{"seed: 1", "seed: 1\nmodule_types: {extension: " + file + "}"}});
  ASSERT_EQ(strong.exit_code, 0) << strong.stderr_text;
  const double v2 = multi_head_speed_cm_s(read_trace(strong.dir + "/trace.csv"), 2.0);
  std::printf("[ inchworm-multi ] gait 13, S E S E S E S: head %.3f cm/s, the rear extension pushes %.3f N "
              "of its 0.356; with 0.712 N: %.3f cm/s\n", v, drag, v2);
  EXPECT_LT(v, 1.43);                  // S E S's speed (ideal 4.5): measured 1.13 over 1-10 s
  EXPECT_GT(drag, 0.6 * 0.356);        // measured 0.26
  EXPECT_GT(v2, 2.0 * v);              // measured 4.16 over 1-10 s
  EXPECT_GT(v2, 0.75 * 4.5);
}
