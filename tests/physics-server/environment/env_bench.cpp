// Analytic pipe colliders against mesh pipes (ODE trimesh) in the same scene:
// step cost and contact quality. Prints figures, asserts nothing. Figures of
// record: docs/benchmarks.md.
//   env_bench [seconds=1]               the benchmark
//   env_bench --write-example-meshes DIR  writes scenes/meshes/straight-pipe.stl, elbow.obj
//
// Scenes (inner diameter 30 mm; rotation chains 40 mm; mu 0.3, dt 500 us):
//  * slide: 4 passive modules (capsules r 12 mm) slide down a 30 degree pipe
//    from rest; theory (rigid, no rolling): x = g (sin 30 - mu cos 30) t^2 / 2;
//  * elbow: a passive module slides down 45 degrees through a 90 degree
//    elbow into a level pipe (depth against the exact bore for all);
//  * rest: 4 passive modules, then 4 rotation modules (capsule + two
//    cylinders; servos holding 0), lie in a horizontal pipe; after 0.5 s of
//    settling, how much they still move (jitter).
// Cost: thread CPU time of World::step (collision + solver), per step.
// Contact quality: depth = deepest point of any body beyond the collider's
// wall (the exact circle; for a mesh its inscribed polygon), sampled body
// surfaces (tests/physics-server/environment/pipe_probe.h), max and mean (of max(0, depth)) over steps;
// jitter = peak-to-peak and RMS of the body centres about their mean (across
// the axis, and along it), and RMS speed.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "environment/pipe_mesh.h"
#include "environment/pipe_path.h"
#include "physics-server/physics/bench_clock.h"
#include "pipe_probe.h"
#include "physics/placement.h"
#include "model/units.h"
#include "physics/world.h"
#include "world_of.h"
#include "determinism/libm_variants.h"

using namespace chainsim;

namespace {

struct Pipe {
  const char* name;
  PipeCollider collider;
  int around;
};

// four modules of `type` in a 2 m straight pipe
WorldConfig scene(const Pipe& p, double slope_deg, const std::vector<std::string>& chain, double diameter) {
  WorldConfig c;
  c.environment.type = EnvironmentType::Pipe;
  c.environment.ground_plane = false;
  PipeSegment s;
  s.length_m = 2.0;
  s.slope_deg = slope_deg;
  c.environment.pipe.segments = {s};
  c.environment.pipe.inner_diameter_m = diameter;
  c.environment.pipe.collider = p.collider;
  c.environment.pipe.mesh_segments = p.around;
  c.ground.mu = 0.3;
  place_types_at_pipe_entry(&c, chain, slope_deg > 0 ? 1.6 - compile_chain(WorldConfig{}, chain).length_m : 0.5);
  return c;
}

struct Figures {
  double us_per_step = 0, contacts = 0, depth_max = -1, depth_mean = 0;
  double slid = 0;                         // slide
  double pp_across = 0, rms_across = 0, pp_along = 0, rms_speed = 0;  // rest
};

// depth of a sphere (x, r) in the wall the collider has: the circle, or for a
// mesh the polygon of `around` flat faces inscribed in it (straight pipes only)
double collider_depth(const PipeLayout& l, const Pipe& p, const Eigen::Vector3d& x, double r) {
  if (p.collider == PipeCollider::Analytic) return pipe_depth(l, x, r);
  const PipePiece& piece = l.pieces[0];
  const Eigen::Vector3d q = x - piece.start.point;
  const double s = q.dot(piece.start.tangent);
  if (s < 0 || s > piece.length_m) return -1;
  const Eigen::Vector3d left = piece.start.up.cross(piece.start.tangent);
  const double u = q.dot(piece.start.up), v = q.dot(left);
  double best = -1;
  for (int k = 0; k < p.around; ++k) {
    const double a = 2 * kPi * (k + 0.5) / p.around;  // face normals (pipe_mesh.cpp ring vertices at 2 pi j / n)
    best = std::max(best, u * std::cos(a) + v * std::sin(a) + r - l.radius_m * std::cos(kPi / p.around));
  }
  return best;
}

Figures slide(const Pipe& p, double seconds) {
  const std::vector<std::string> chain(4, "passive");
  WorldConfig c = scene(p, 30, chain, 0.03);
  World w = world_of(c, chain);
  const PipeLayout l = layout_pipe(c.environment.pipe);
  const std::vector<ModuleDef> defs = chain_defs(c, chain);
  const Eigen::Vector3d start = w.chain_com();
  Figures f;
  const int steps = static_cast<int>(seconds / 5e-4);
  double cost = 0;
  int probes = 0;
  for (int k = 0; k < steps; ++k) {
    const double t0 = bench::cpu_us();
    w.step();
    cost += bench::cpu_us() - t0;
    f.contacts += w.last_contact_count();
    if (k % 4 == 0) {
      const double d = probe_bodies(w, defs, l, 8, [&](const Eigen::Vector3d& x, double r) {
                         return collider_depth(l, p, x, r);
                       }).depth_m;
      f.depth_max = std::max(f.depth_max, d);
      f.depth_mean += std::max(0.0, d);
      ++probes;
    }
  }
  f.us_per_step = cost / steps;
  f.contacts /= steps;
  f.depth_mean /= probes;
  f.slid = -(w.chain_com() - start).dot(l.entry.tangent);
  return f;
}

// a passive module slides down 45 degrees through a 90 degree elbow (bend
// radius 60 mm, turning left) into a level pipe; depth against the exact bore
// (for a mesh that includes its faceting, R (1 - cos(pi/n)))
Figures elbow(const Pipe& p, double seconds, double* exit_time_s) {
  WorldConfig c;
  c.environment.type = EnvironmentType::Pipe;
  c.environment.ground_plane = false;
  PipeSegment a, e, b;
  a.length_m = 0.2;
  e.type = PipeSegment::Type::Elbow;
  e.bend_radius_m = 0.06;
  e.direction_deg = 90;
  b.length_m = 1.5;
  c.environment.pipe = {};
  c.environment.pipe.segments = {a, e, b};
  c.environment.pipe.slope_deg = -45;
  c.environment.pipe.collider = p.collider;
  c.environment.pipe.mesh_segments = p.around;
  const std::vector<std::string> chain = {"passive"};  // a docked chain is rigid: longer ones jam in the bend
  c.ground.mu = 0.3;
  place_types_at_pipe_entry(&c, chain, 0.01);
  World w = world_of(c, chain);
  const PipeLayout l = layout_pipe(c.environment.pipe);
  const std::vector<ModuleDef> defs = chain_defs(c, chain);
  Figures f;
  *exit_time_s = -1;
  const int steps = static_cast<int>(seconds / 5e-4);
  double cost = 0;
  int probes = 0;
  for (int k = 0; k < steps; ++k) {
    const double t0 = bench::cpu_us();
    w.step();
    cost += bench::cpu_us() - t0;
    f.contacts += w.last_contact_count();
    if (*exit_time_s < 0 && (w.chain_com() - l.pieces[2].start.point).dot(l.pieces[2].start.tangent) > 0)
      *exit_time_s = (k + 1) * 5e-4;
    if (k % 4 == 0) {
      const double d = probe_pipe(w, defs, l, 8).depth_m;
      f.depth_max = std::max(f.depth_max, d);
      f.depth_mean += std::max(0.0, d);
      ++probes;
    }
  }
  f.us_per_step = cost / steps;
  f.contacts /= steps;
  f.depth_mean /= probes;
  f.slid = (w.chain_com() - l.pieces[2].start.point).dot(l.pieces[2].start.tangent);
  return f;
}

Figures rest(const Pipe& p, const std::string& type, double diameter, double seconds) {
  const std::vector<std::string> chain(4, type);
  WorldConfig c = scene(p, 0, chain, diameter);
  World w = world_of(c, chain);  // rotation modules: servos powered, holding the chain straight
  const PipeLayout l = layout_pipe(c.environment.pipe);
  const std::vector<ModuleDef> defs = chain_defs(c, chain);
  for (int k = 0; k < 1000; ++k) w.step();  // settle 0.5 s
  const int steps = static_cast<int>(seconds / 5e-4);
  int nb = 0;
  for (int m = 0; m < w.module_count(); ++m) nb += w.body_count(m);
  std::vector<std::vector<Eigen::Vector3d>> track(nb);
  Figures f;
  double cost = 0, speed2 = 0;
  for (int k = 0; k < steps; ++k) {
    const double t0 = bench::cpu_us();
    w.step();
    cost += bench::cpu_us() - t0;
    f.contacts += w.last_contact_count();
    int i = 0;
    for (int m = 0; m < w.module_count(); ++m)
      for (int b = 0; b < w.body_count(m); ++b, ++i) {
        const World::BodyState s = w.body_state(m, b);
        track[i].push_back(s.position);
        speed2 += s.linear_velocity.squaredNorm();
      }
    if (k % 4 == 0) {
      const double d = probe_bodies(w, defs, l, 8, [&](const Eigen::Vector3d& x, double r) {
                         return collider_depth(l, p, x, r);
                       }).depth_m;
      f.depth_max = std::max(f.depth_max, d);
      f.depth_mean += std::max(0.0, d) * 4 / steps;
    }
  }
  f.us_per_step = cost / steps;
  f.contacts /= steps;
  f.rms_speed = std::sqrt(speed2 / (static_cast<double>(steps) * nb));
  double sum2 = 0;
  for (const auto& t : track) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& x : t) mean += x;
    mean /= static_cast<double>(t.size());
    for (const auto& x : t) {
      const Eigen::Vector3d d = x - mean;
      const double along = d.x();  // the pipe runs along +x
      const double across = std::hypot(d.y(), d.z());
      f.pp_across = std::max(f.pp_across, 2 * across);
      f.pp_along = std::max(f.pp_along, 2 * std::fabs(along));
      sum2 += across * across;
    }
  }
  f.rms_across = std::sqrt(sum2 / (static_cast<double>(steps) * nb));
  return f;
}

int write_example_meshes(const std::string& dir) {
  PipeSpec straight;
  straight.inner_diameter_m = 0.03;
  PipeSegment s;
  s.length_m = 0.2;
  straight.segments = {s};
  const TriMesh a = pipe_solid_mesh(layout_pipe(straight), 16, 0.002);
  write_stl(a, dir + "/straight-pipe.stl",
            "chainsim straight pipe: bore 30 mm, wall 2 mm, 0.2 m along +x from the origin");
  PipeSpec elbow;
  elbow.inner_diameter_m = 0.03;
  PipeSegment e;
  e.type = PipeSegment::Type::Elbow;
  e.bend_radius_m = 0.05;
  e.angle_deg = 90;
  e.direction_deg = 90;
  elbow.segments = {e};
  const TriMesh b = pipe_solid_mesh(layout_pipe(elbow), 16, 0.002);
  write_obj(b, dir + "/elbow.obj",
            "chainsim elbow: bore 30 mm, wall 2 mm, bend radius 50 mm, 90 degrees; enters at the "
            "origin along +x, leaves at (0.05, 0.05, 0) along +y. Metres. Written by env_bench "
            "--write-example-meshes");
  std::printf("%s/straight-pipe.stl: %zu triangles\n%s/elbow.obj: %zu triangles\n", dir.c_str(),
              a.triangles.size(), dir.c_str(), b.triangles.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  chainsim::use_baseline_libm("env_bench", argv);  // the libm chainsim uses
  if (argc > 2 && std::strcmp(argv[1], "--write-example-meshes") == 0) return write_example_meshes(argv[2]);
  const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
  const Pipe pipes[] = {{"analytic", PipeCollider::Analytic, 0},
                        {"mesh 16", PipeCollider::Mesh, 16},
                        {"mesh 32", PipeCollider::Mesh, 32},
                        {"mesh 64", PipeCollider::Mesh, 64}};
  const double theory = 0.5 * 9.81 * (0.5 - 0.3 * std::cos(kPi / 6)) * seconds * seconds;
  std::printf("slide: 4 passive modules down a 30 degree pipe, %.1f s (theory %.3f m)\n", seconds, theory);
  std::printf("%-10s %9s %9s %12s %12s %9s\n", "collider", "us/step", "contacts", "depth max mm",
              "depth avg mm", "slid m");
  for (const Pipe& p : pipes) {
    const Figures f = slide(p, seconds);
    std::printf("%-10s %9.1f %9.1f %12.3f %12.3f %9.3f\n", p.name, f.us_per_step, f.contacts,
                f.depth_max * 1e3, f.depth_mean * 1e3, f.slid);
  }
  std::printf("\nelbow: a passive module slides down 45 degrees through a 90 degree elbow, %.1f s\n", seconds);
  std::printf("%-10s %9s %9s %12s %12s %12s %16s\n", "collider", "us/step", "contacts", "depth max mm",
              "depth avg mm", "com out at s", "com past elbow m");
  for (const Pipe& p : pipes) {
    double out_s;
    const Figures f = elbow(p, seconds, &out_s);
    std::printf("%-10s %9.1f %9.1f %12.3f %12.3f %12.3f %16.3f\n", p.name, f.us_per_step, f.contacts,
                f.depth_max * 1e3, f.depth_mean * 1e3, out_s, f.slid);
  }
  for (const char* type : {"passive", "rotation"}) {
    const double d = std::string(type) == "passive" ? 0.03 : 0.04;
    std::printf("\nrest: 4 %s modules in a horizontal pipe (bore %.0f mm), %.1f s after 0.5 s settling\n",
                type, d * 1e3, seconds);
    std::printf("%-10s %9s %9s %12s %12s %11s %11s %10s %11s\n", "collider", "us/step", "contacts",
                "depth max mm", "depth avg mm", "pp across", "rms across", "pp along", "rms speed");
    std::printf("%-10s %9s %9s %12s %12s %11s %11s %10s %11s\n", "", "", "", "", "", "um", "um", "um", "mm/s");
    for (const Pipe& p : pipes) {
      const Figures f = rest(p, type, d, seconds);
      std::printf("%-10s %9.1f %9.1f %12.3f %12.3f %11.1f %11.1f %10.1f %11.2f\n", p.name,
                  f.us_per_step, f.contacts, f.depth_max * 1e3, f.depth_mean * 1e3, f.pp_across * 1e6,
                  f.rms_across * 1e6, f.pp_along * 1e6, f.rms_speed * 1e3);
    }
  }
  return 0;
}
