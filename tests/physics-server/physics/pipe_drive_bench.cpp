// Cost of the pipe drives: thread CPU time of World::step for chains driven
// by helicoidal modules in pipes of 40 mm bore (the shipped scenes' pipes), and
// for the inchworm's modules. Prints figures, asserts nothing. Figures of
// record: docs/benchmarks.md ("Pipe drives").
//   pipe_drive_bench [seconds=3]
//
// Cases (no firmware: every helicoidal module gets full drive, the supports
// hold their arms at 90 degrees, the extension holds its length):
//  * H level / H vertical: one helicoidal module, as scenes/helicoidal-{0,90};
//  * TRRH elbow / THRHRHRHH elbow: scenes/elbow-THRHRHRHH's pipe (0.55 m
//    straight, a 90 degree elbow of bend radius 80 mm to the left, 0.55 m
//    straight), no steering;
//  * SES vertical: the inchworm of scenes/inchworm-90 gripping.
//  * H level, force on the pig: the helicoidal module as it was before it
//    drove through its wheels (scenes/modules/helicoidal.yaml at 27cb164^: a
//    10 g capsule pushed along its axis by a screw drive, 0.16 N stall,
//    3 cm/s free), the "before" of the wheels' cost (issue 11's requirement 5).
// Each case with QuickStep (the scenes' 30 iterations) and with the exact
// solver (physics.solver: exact).
// Per case: us per step, us per step per helicoidal module, contact joints per
// step, and how far the head moved (a sanity check that the drive works).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_clock.h"
#include "model/module_file.h"
#include "physics/placement.h"
#include "physics/world.h"
#include "world_of.h"
#include "determinism/libm_variants.h"

using namespace chainsim;

namespace {

struct Case {
  const char* name;
  std::string chain;   // module letters
  double slope_deg;
  bool elbow;
  bool force_on_pig = false;  // the helicoidal module before its wheels
};

// scenes/modules/helicoidal.yaml before 27cb164 (its comments left out)
const char* kForceOnPigHelicoidal = R"(type: helicoidal
description: "helicoidal module before its wheels: a pig body pushed along its axis by a screw drive"
bodies:
  - {name: pig, shape: capsule, radius_m: 0.0125, length_m: 0.021, mass_kg: 0.010, position_m: [-0.023, 0, 0],
     rotation: {axis: [0, 1, 0], angle_deg: 90}}
actuators:
  - {name: screw, type: screw_drive, body: pig, direction: [0, 0, 1], fmax_n: 0.16, v_free_m_s: 0.03}
sensors:
  - {name: screw_current, type: motor_current, actuator: screw, channel: 0}
docking:
  front: {body: pig, position_m: [0, 0, 0]}
  back: {body: pig, position_m: [-0.046, 0, 0]}
)";

std::string type_of(char c) {
  switch (c) {
    case 'T': return "touch";
    case 'R': return "rotation";
    case 'H': return "helicoidal";
    case 'S': return "support";
    case 'E': return "extension";
    default: return "passive";
  }
}

std::vector<std::string> chain_of(const Case& k) {
  std::vector<std::string> out;
  for (char m : k.chain) out.push_back(type_of(m));
  return out;
}

WorldConfig scene(const Case& k, WorldConfig::Solver solver) {
  WorldConfig c;
  c.solver = solver;
  if (k.force_on_pig) c.module_types = {load_module_text(kForceOnPigHelicoidal, "<force-on-pig helicoidal>")};
  c.environment.type = EnvironmentType::Pipe;
  c.environment.pipe.inner_diameter_m = 0.04;
  PipeSegment s;
  s.length_m = k.elbow ? 0.55 : 0.4;  // the long chain fits the entry leg
  s.slope_deg = k.slope_deg;
  c.environment.pipe.segments = {s};
  if (k.elbow) {
    PipeSegment e;
    e.type = PipeSegment::Type::Elbow;
    e.bend_radius_m = 0.08;
    e.angle_deg = 90;
    e.direction_deg = 90;
    PipeSegment out;
    out.length_m = 0.55;
    c.environment.pipe.segments.push_back(e);
    c.environment.pipe.segments.push_back(out);
  }
  c.ground.mu = k.chain.find('S') != std::string::npos ? 0.6 : 0.05;  // as the scenes
  place_types_at_pipe_entry(&c, chain_of(k), 0.01);
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  chainsim::use_baseline_libm("pipe_drive_bench", argv);  // the libm chainsim uses
  const char* usage = "pipe_drive_bench [seconds=3]";
  bench::help_or_continue(argc, argv, usage);
  if (argc > 2) {
    std::fprintf(stderr, "pipe_drive_bench: one argument at most\nusage: %s\n", usage);
    return 2;
  }
  const double seconds = argc > 1 ? bench::positive(argv[1], "seconds", usage) : 3.0;
  const double kDeg = 3.14159265358979323846 / 180.0;
  const std::vector<Case> cases = {{"H level, pig force", "H", 0, false, true},
                                   {"H level", "H", 0, false},
                                   {"H vertical", "H", 90, false},
                                   {"TRRH elbow", "TRRH", 0, true},
                                   {"THRHRHRHH elbow", "THRHRHRHH", 0, true},
                                   {"THRHRHRHH, pig force", "THRHRHRHH", 0, true, true},
                                   {"SES vertical", "SES", 90, false}};
  std::printf("%.1f s simulated per case after 0.5 s of settling; thread CPU time\n", seconds);
  std::printf("%-20s %-9s %8s %10s %12s %10s %10s\n", "case", "solver", "bodies", "us/step", "us/step/H",
              "contacts", "moved mm");
  for (const Case& k : cases)
    for (WorldConfig::Solver solver : {WorldConfig::Solver::QuickStep, WorldConfig::Solver::Exact}) {
      World w = world_of(scene(k, solver), chain_of(k));
      int n_h = 0, bodies = 0;
      for (int m = 0; m < w.module_count(); ++m) {
        bodies += w.body_count(m);
        const std::string& t = w.module_type(m);
        if (t == "helicoidal") {
          ++n_h;
          w.set_servo_setpoint(m, 0, 1.0);
        } else if (t == "support") {
          w.set_servo_setpoint(m, 0, 90 * kDeg);
        }
      }
      for (int i = 0; i < 1000; ++i) w.step();
      const Eigen::Vector3d start = w.body_state(0, 0).position;
      const int steps = static_cast<int>(seconds / (w.dt_us() * 1e-6));
      long contacts = 0;
      const double t0 = bench::cpu_us();
      for (int i = 0; i < steps; ++i) {
        w.step();
        contacts += w.last_contact_count();
      }
      const double us = (bench::cpu_us() - t0) / steps;
      std::printf("%-20s %-9s %8d %10.2f %12.2f %10.2f %10.1f\n", k.name,
                  solver == WorldConfig::Solver::Exact ? "exact" : "quickstep", bodies, us,
                  n_h > 0 ? us / n_h : 0.0, static_cast<double>(contacts) / steps,
                  (w.body_state(0, 0).position - start).norm() * 1e3);
    }
  return 0;
}
