// `chainsim bench --bench B.yaml --setpoints S.csv --out OUT.csv`: one servo on
// a test stand, simulated with the robot's own ServoModel on an ODE hinge, driven
// by a set-point CSV; writes the output-shaft angle and the filtered current
// (what the ADC sees) at the CSV's times. docs/servo-bench.md describes the
// model, the files and the agreement with the continuous equations.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/actuators/servo_model.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the `bench` subcommand on `app`; its callback runs the bench
void add_bench_command(CLI::App& app);

// after app.parse(): the bench's exit code (0 ok, 1 bad input or output
// file), or -1 when the bench subcommand was not given
int bench_command_exit_code();

// ---- the stand as a function (used by `chainsim calibrate`)

struct BenchConfig {
  ServoParams servo;                 // Table 1 defaults
  double load_inertia_kgm2 = 3.0e-6;
  double load_torque_nm = 0.0;
  int64_t dt_us = 500;
};

// a bench file error, "file:line:column: what"
struct BenchError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// reads a bench file (YAML; docs/servo-bench.md); throws BenchError
BenchConfig load_bench_config(const std::string& file);

struct BenchSample {
  double angle_deg = 0;
  double current_a = 0;   // the filtered current
};

// how the stand's one hinge is stepped: ODE's exact solver (what `chainsim
// bench` does), or the same step law solved in closed form for the one degree
// of freedom ((J_load/h + D) w' = J_load w/h + D v + tau_load), ~50x faster,
// used by the calibration's optimiser; the two agree to solver round-off.
enum class BenchSolver { ode_exact, closed_form };

// the bench's response at the times t_s (strictly increasing) to the
// set-points (degrees, each held from its time until the next)
std::vector<BenchSample> simulate_bench(const BenchConfig& b, const std::vector<double>& t_s,
                                        const std::vector<double>& setpoint_deg,
                                        BenchSolver solver = BenchSolver::ode_exact);

}  // namespace chainsim
