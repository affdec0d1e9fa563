// Physics-only replay of a run. See replay.h.
#include "cosim/replay.h"

#include <chrono>
#include <cmath>

#include "output/sha256.h"
#include "output/trace_writer.h"
#include "physics/world.h"

namespace chainsim {

double replay_physics(const Scene& scene, const std::vector<ServoCommand>& commands,
                      std::string* trace_sha256) {
  const ChainModel chain = compile_chain(scene);
  World world(scene.world, chain);
  TraceWriter trace(world, TraceWriter::interval_for(world, scene.trace_hz), sensor_columns(chain));
  Sha256 sha;
  sha.update(trace.header().data(), trace.header().size());
  std::string row;
  row.reserve(1 << 14);
  auto write_due_row = [&] {
    if (trace.row_due(&row)) sha.update(row.data(), row.size());
  };
  const auto wall0 = std::chrono::steady_clock::now();
  const int64_t end_us = std::llround(scene.duration_s * 1e6);
  const int substeps = static_cast<int>(scene.tick_us / world.dt_us());
  size_t next = 0;
  write_due_row();
  for (int64_t t = 0; t < end_us; t += scene.tick_us) {
    for (; next < commands.size() && commands[next].t_us <= t; ++next) {
      const ServoCommand& c = commands[next];
      world.set_servo_enabled(c.module, c.servo, c.enabled);
      if (c.enabled) world.set_servo_setpoint_wire(c.module, c.servo, c.setpoint_wire);
    }
    for (int k = 0; k < substeps; ++k) {
      world.step();
      write_due_row();
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (trace_sha256) *trace_sha256 = sha.hex();
  return wall;
}

}  // namespace chainsim
