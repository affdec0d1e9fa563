// Two runs of one scene compared channel by channel, endpoint by endpoint:
// typically the programs built for this computer against the board's own
// binaries in gpsim (`chainsim run --compare native,pic`,
// docs/pic-in-the-loop.md). For each endpoint the first place where the two
// differ: its time in each run, the channel (log line, I2C frame, Sout edge,
// servo set-point, fault, I2C address) and both values. Then how far the two
// trajectories drift apart. The board's timing is not the PC's (a servo
// takes a pulse every 20 ms, a log line leaves the UART after its
// characters), so the same sequence of values at slightly different times is
// no divergence: times within the tolerances below are the same.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "output/run_reader.h"

namespace chainsim {

struct CompareTolerances {
  double setpoint_lag_s = 0.03;  // a set-point may show up this much later or earlier (a 20 ms servo frame, a tick)
  double setpoint_deg = 0.1;     // a rotary servo's set-point (the board's pulse: 0.036 degree steps)
  double setpoint_mm = 0.05;     // a linear servo's
  double command = 0.005;        // a screw drive's or DC motor's command (-1..1)
  double sout_s = 0.05;          // a Sout edge may move this much
  double end_slack_s = 0.1;      // what each run did in its last moments is not held against the other
};

struct Divergence {
  int endpoint = 0;
  std::string who;       // "module 3 (rotation)", "central control (central)"
  std::string channel;   // "log", "i2c", "sout", "setpoint m3.s0", "fault", "address"
  double t_a = -1, t_b = -1;  // when each run shows it; -1: it does not
  std::string a, b;      // the two values ("(none)" where one run has nothing)
};

struct ChannelTally {
  std::string channel;
  int compared = 0;      // items (lines, frames, edges, rows) both runs had and that agreed up to the divergence
  bool diverged = false;
};

struct EndpointComparison {
  int endpoint = 0;
  std::string who;
  std::vector<Divergence> divergences;  // the first of each channel that diverged, earliest first
  std::vector<ChannelTally> tally;
};

// a set-point column of run b against run a, best aligned: b's values are a's
// lag_s later (negative: earlier), with rms left over
struct SetpointLag {
  std::string column;
  double lag_s = 0;
  double rms = 0;          // after the shift, in the column's unit
  double rms_unshifted = 0;
};

struct CompareReport {
  std::string label_a, label_b;
  std::string scene;
  double end_a_s = 0, end_b_s = 0;
  std::vector<EndpointComparison> endpoints;
  // drift of the trajectories over the rows both traces have
  double head_apart_end_m = 0, head_apart_max_m = 0, head_apart_max_at_s = 0;
  double angle_rms_deg = 0;         // over every rotary servo's measured angle, the rows both have
  std::string angle_worst;          // the servo column with the largest RMS difference
  double angle_worst_rms_deg = 0;
  std::vector<SetpointLag> lags;    // every set-point column that moves, searched within +-1 s
  double distance_a_m = 0, distance_b_m = 0;  // each run's chain displacement (summary.json)
  double rtf_a = 0, rtf_b = 0;                // real-time factors
  int exit_a = 0, exit_b = 0;
  CompareTolerances tol;

  // the earliest divergence of all, or nullptr
  const Divergence* first() const;
};

// throws RunReadError when a run directory lacks what is compared
CompareReport compare_runs(RunReader& a, RunReader& b, const std::string& label_a, const std::string& label_b,
                           const CompareTolerances& tol = {});

std::string compare_text(const CompareReport& r);

// `--compare A,B` of run and test: two different targets (native, pic), or
// an empty list and *error saying what is wrong with text
std::vector<Target> parse_compare_targets(const std::string& text, std::string* error);
nlohmann::json compare_json(const CompareReport& r);

}  // namespace chainsim
