// Test and benchmark helper: how deep the bodies of a World are in the wall
// of a pipe layout, measured independently of the colliders by sampling each
// body's surface densely against the exact bore (pipe_path.h).
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "model/module_def.h"
#include "environment/pipe_path.h"
#include "model/units.h"
#include "physics/world.h"

namespace chainsim {

// ModuleDef of each module of chain (compiled as the World compiles it)
inline std::vector<ModuleDef> chain_defs(const WorldConfig& cfg, const std::vector<std::string>& chain) {
  return compile_chain(cfg, chain).modules;
}

struct PipeProbe {
  double depth_m = -std::numeric_limits<double>::infinity();  // deepest body point beyond the wall
  bool all_inside = true;   // every body's centre is inside the bore of some piece
};

// samples: points per line / circle; depth(x, r): how deep a sphere (x, r)
// is in the wall (default: the layout's exact bore)
template <typename Depth>
PipeProbe probe_bodies(const World& w, const std::vector<ModuleDef>& defs, const PipeLayout& layout,
                       int samples, const Depth& depth) {
  PipeProbe out;
  auto take = [&](const Eigen::Vector3d& x, double r) {
    out.depth_m = std::max(out.depth_m, depth(x, r));
  };
  for (int m = 0; m < w.module_count(); ++m)
    for (int b = 0; b < w.body_count(m); ++b) {
      const BodyDef& bd = defs[m].bodies[b];
      const World::BodyState s = w.body_state(m, b);
      const Eigen::Quaterniond q(s.quaternion_wxyz[0], s.quaternion_wxyz[1], s.quaternion_wxyz[2],
                                 s.quaternion_wxyz[3]);
      const Eigen::Matrix3d r = q.toRotationMatrix();
      const Eigen::Vector3d c = s.position;
      const double centre = pipe_depth(layout, c, 0.0);  // -infinity: no piece owns it
      if (!(std::isfinite(centre) && centre < 0)) out.all_inside = false;
      switch (bd.shape) {
        case Shape::Sphere: take(c, bd.radius_m); break;
        case Shape::Capsule:
          for (int i = 0; i <= samples; ++i)
            take(c + (static_cast<double>(i) / samples - 0.5) * bd.length_m * r.col(2), bd.radius_m);
          break;
        case Shape::Cylinder:
          for (int i = 0; i <= samples; ++i)
            for (int j = 0; j < samples; ++j) {
              const double a = 2 * kPi * j / samples;
              take(c + (static_cast<double>(i) / samples - 0.5) * bd.length_m * r.col(2) +
                       bd.radius_m * (std::cos(a) * r.col(0) + std::sin(a) * r.col(1)),
                   0.0);
            }
          break;
        case Shape::Box:
          for (int i = 0; i <= samples; ++i)
            for (int j = 0; j <= samples; ++j)
              for (int k = 0; k <= samples; ++k) {
                const Eigen::Vector3d f(static_cast<double>(i) / samples - 0.5,
                                        static_cast<double>(j) / samples - 0.5,
                                        static_cast<double>(k) / samples - 0.5);
                take(c + r * f.cwiseProduct(bd.box_m), 0.0);
              }
          break;
      }
    }
  return out;
}

inline PipeProbe probe_pipe(const World& w, const std::vector<ModuleDef>& defs,
                            const PipeLayout& layout, int samples = 24) {
  return probe_bodies(w, defs, layout, samples,
                      [&](const Eigen::Vector3d& x, double r) { return pipe_depth(layout, x, r); });
}

// a module type of one body of shape (for colliders other than the built-ins')
inline ModuleDef one_body_module(const std::string& type, Shape shape, double radius, double length,
                                 const Eigen::Vector3d& box, double mass) {
  ModuleDef d;
  d.type = type;
  d.description = "test body";
  BodyDef b;
  b.name = "body";
  b.shape = shape;
  b.radius_m = radius;
  b.length_m = length;
  b.box_m = box;
  b.mass_kg = mass;
  const double extent = shape == Shape::Box ? box.x()
                        : shape == Shape::Sphere ? 2 * radius
                        : shape == Shape::Capsule ? length + 2 * radius
                                                  : length;
  b.pose.position = Eigen::Vector3d(-extent / 2, 0, 0);
  // capsule and cylinder axes (body z) along the chain (module x)
  if (shape == Shape::Capsule || shape == Shape::Cylinder)
    b.pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
  d.bodies.push_back(b);
  d.front.body = 0;
  d.back.body = 0;
  d.back.frame.position = Eigen::Vector3d(-extent, 0, 0);
  return d;
}

}  // namespace chainsim
