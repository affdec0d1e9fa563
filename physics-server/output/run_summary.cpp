// summary.json. See run_summary.h.
#include "output/run_summary.h"

#include <cstdio>

namespace chainsim {

namespace {

// the constraint solver, and how often the exact one met a degenerate pivot
nlohmann::json solver_json(const WorldConfig& world, int64_t degenerate_lcp_steps) {
  if (world.solver == WorldConfig::Solver::Exact)
    return {{"name", "exact"}, {"degenerate_lcp_steps", degenerate_lcp_steps}};
  return {{"name", "quickstep"}, {"iterations", world.solver_iterations}};
}

}  // namespace

nlohmann::json summary_json(const Scene& scene, const RunSummary& run) {
  nlohmann::json mods = nlohmann::json::array();
  for (const EndpointSummary& e : run.endpoints) {
    nlohmann::json m = {{"index", e.index},
                        {"type", e.type},
                        {"program", e.program},
                        {"target", e.target},
                        {"pid", e.pid},
                        {"fault", e.fault.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.fault)},
                        {"exchanges", e.exchanges}};
    if (e.energy_j) m["energy_j"] = *e.energy_j;
    if (!e.pic.is_null()) m["pic"] = e.pic;
    if (e.i2c_address != 0) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", e.i2c_address);
      m["i2c_address"] = hex;
      m["addressed_at_s"] = static_cast<double>(e.addressed_us) / 1e6;  // 0.007, not 0.006999999999999999
    } else {
      m["i2c_address"] = nullptr;  // it never answered discovery (or lost its address)
      m["addressed_at_s"] = nullptr;
    }
    mods.push_back(m);
  }
  const double sim_s = run.sim_time_us * 1e-6;
  const double wall = run.wall_time_s;
  const Eigen::Vector3d& d = run.displacement_m;
  return {{"scene", scene.name},
          {"scene_source", scene.source},
          {"seed", scene.world.seed},
          {"sim_time_s", sim_s},
          {"wall_time_s", wall},
          {"real_time_factor", wall > 0 ? sim_s / wall : 0.0},
          {"dt_us", scene.world.dt_us},
          {"tick_us", scene.tick_us},
          {"solver", solver_json(scene.world, run.degenerate_lcp_steps)},
          {"on_module_fault", run.limp_mode ? "limp" : "stop"},
          {"trace_file", "trace.csv"},
          {"trace_sha256", run.trace_sha256},
          {"exchanges", run.exchanges},
          {"modules", mods},
          {"chain",
           {{"displacement_m", {d.x(), d.y(), d.z()}},
            {"distance_m", d.norm()},
            {"speed_m_s", sim_s > 0 ? d.norm() / sim_s : 0.0}}},
          {"discovery",
           {{"judged_at_s", static_cast<double>(run.discovery_us) / 1e6},
            {"judged", run.discovery_judged},
            {"silent", run.silent},
            {"allowed_silent", run.allowed_silent}}},
          {"exit_code", run.exit_code},
          {"stopped_by", run.stopped_by.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.stopped_by)},
          {"early_stop", run.early_stop.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.early_stop)}};
}

}  // namespace chainsim
