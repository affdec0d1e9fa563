// The servo test stand: one servo (the robot's ServoModel) turning a load on
// an ODE hinge, driven by set-points; what a real bench records comes out:
// the output-shaft angle and the filtered motor current (what the ADC sees).
// docs/servo-bench.md describes the model and its agreement with the
// continuous equations.
#pragma once

#include <cstdint>
#include <vector>

#include "analysis/servo_bench/bench_config.h"

namespace chainsim {

struct BenchSample {
  double angle_deg = 0;
  double current_a = 0;   // the filtered current
};

// how the stand's one hinge is stepped: ODE's exact solver (what `chainsim
// bench` does), or the same step law solved in closed form for the one degree
// of freedom ((J_load/h + D) w' = J_load w/h + D v + tau_load), ~50x faster,
// used by the calibration's optimiser; the two agree within 0.0021 degrees
// and 12 uA on the moves of tests/physics-server/analysis/servo_bench.
enum class BenchSolver { ode_exact, closed_form };

// the bench's response at the times t_s (strictly increasing) to the
// set-points (degrees, each held from its time until the next). The hinge
// starts at rest at the first set-point; angles are continuous (no wrap).
// Throws std::invalid_argument for empty or unequal inputs. With count below
// the inputs' size only the first count samples are simulated and returned
// (the same values as the whole run gives for them).
std::vector<BenchSample> simulate_bench(const BenchConfig& b, const std::vector<double>& t_s,
                                        const std::vector<double>& setpoint_deg,
                                        BenchSolver solver = BenchSolver::ode_exact,
                                        size_t count = SIZE_MAX);

// several benches (the same step dt_us) on the same set-points, stepped side
// by side: result i is bench i's first counts[i] samples, byte for byte what
// simulate_bench gives it alone. On one core two closed-form benches run in
// about 0.75-0.95 of the time of the two one after the other, by the VM's
// state (servo_stand_bench: each step waits on its own chain of dependent
// operations, a division among them; two chains overlap). Throws
// std::invalid_argument as simulate_bench, and for steps that differ.
std::vector<std::vector<BenchSample>> simulate_benches(const std::vector<const BenchConfig*>& b,
                                                       const std::vector<double>& t_s,
                                                       const std::vector<double>& setpoint_deg, BenchSolver solver,
                                                       const std::vector<size_t>& counts);

}  // namespace chainsim
