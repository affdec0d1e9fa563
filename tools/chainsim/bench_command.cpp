// `chainsim bench`: options in, the servo_bench library, exit codes out.
#include "chainsim/bench_command.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "analysis/servo_bench/bench_config.h"
#include "analysis/servo_bench/bench_csv.h"
#include "analysis/servo_bench/servo_stand.h"
#include "readers/csv_table.h"

namespace chainsim {
namespace {

struct ServoBenchArgs {
  std::string bench;
  std::string setpoints;
  std::string out;
  bool quiet = false;
};

ServoBenchArgs g_servo_bench_args;

// the whole file or nothing: no output file is left on error
void write_output(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw BenchError(path + ": cannot write the output file");
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) throw BenchError(path + ": cannot write the output file");
}

int run_bench_command(const ServoBenchArgs& a) {
  try {
    const BenchConfig b = a.bench.empty() ? BenchConfig{} : load_bench_config(a.bench);
    const SetpointProgram program = read_setpoints(a.setpoints);
    const std::vector<BenchSample> samples = simulate_bench(b, program.t_s, program.setpoint_deg);
    write_output(a.out, format_bench_csv(program, samples));
    if (!a.quiet)
      std::fprintf(stderr, "chainsim bench: %zu rows, %.6f s simulated at dt %lld us -> %s\n",
                   program.t_s.size(), program.t_s.back() - program.t_s.front(),
                   static_cast<long long>(b.dt_us), a.out.c_str());
    return 0;
  } catch (const BenchError& e) {
    std::fprintf(stderr, "chainsim bench: %s\n", e.what());
    return 1;
  } catch (const CsvError& e) {
    std::fprintf(stderr, "chainsim bench: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim bench: internal error: %s\n", e.what());
    return 3;
  }
}

}  // namespace

Command add_bench_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "bench",
      "servo test stand: the robot's servo model on one hinge with a load, driven by a set-point "
      "CSV (t_s,setpoint_deg); writes t_s,setpoint_deg,angle_deg,current_a (docs/servo-bench.md)");
  sub->add_option("--bench,-b", g_servo_bench_args.bench,
                  "bench file (YAML: servo, load, sensors, sim; every key optional; default: the "
                  "paper's Table 1 servo with a 3e-6 kg m^2 load)");
  sub->add_option("--setpoints,-s", g_servo_bench_args.setpoints, "set-point CSV with columns t_s,setpoint_deg")
      ->required();
  sub->add_option("--out,-o", g_servo_bench_args.out, "CSV to write: t_s,setpoint_deg,angle_deg,current_a")
      ->required();
  sub->add_flag("--quiet,-q", g_servo_bench_args.quiet, "print only errors");
  return {sub, [] { return run_bench_command(g_servo_bench_args); }};
}


}  // namespace chainsim
