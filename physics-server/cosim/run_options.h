// What a run is asked to do (RunOptions), what it gives back (RunResult) and
// who may watch it as it happens (RunObserver).
#pragma once

#include <cstdint>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace chainsim {

enum class FaultMode { Stop, Limp };
// what a physics divergence does (physics/divergence.h); a non-finite state always stops
enum class DivergenceMode { Stop, Warn };

// exit codes of `chainsim run`
constexpr int kExitOk = 0;
constexpr int kExitBadInput = 1;     // scene or options
constexpr int kExitModuleFault = 2;  // a module crashed, hung or broke the protocol
constexpr int kExitInternal = 3;
constexpr int kExitDivergence = 4;   // the physics diverged (non-finite or beyond the documented bounds)
constexpr int kExitOutput = 5;       // an output file could not be written (disk full, I/O error)
constexpr int kExitSilentModule = 6; // a module never answered discovery (Scene::discovery_s)
constexpr int kExitInterrupted = 130;

// watches a run as it happens (the live view); called from the simulation
// loop, so every method must return quickly and never block on a client.
// Nothing it does can change the simulation's result.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  virtual void started(const nlohmann::json& scene, const std::string& trace_header) = 0;
  virtual void trace_row(const std::string& row) = 0;      // one CSV line, newline included
  virtual void bus_line(int64_t t_us, const char* line) = 0;
  // a log line of endpoint e (modules/NN-TYPE.log)
  virtual void module_log(int endpoint, int64_t t_us, const char* line) { (void)endpoint, (void)t_us, (void)line; }
  virtual void finished(const nlohmann::json& summary) = 0;
};

struct RunOptions {
  std::string out_dir;                  // run directory to write
  FaultMode on_fault = FaultMode::Stop;
  DivergenceMode on_divergence = DivergenceMode::Stop;
  double module_timeout_s = 10.0;       // wall clock, per exchange
  std::set<int> attach;                 // endpoints the user starts by hand
  std::string firmware_dir;             // DIR[:DIR...] searched for programs first, then next to chainsim
  bool overrun_warn = false;            // a PIC program over its CPU budget warns (--on-overrun=warn) instead of faulting
  bool progress = false;                // progress on stderr: one line rewritten on a terminal,
  bool progress_terminal = false;       // else a new line each time
  double progress_every_s = 1.0;        // wall-clock seconds between progress reports
  bool quiet = false;                   // no messages on stderr except errors
  RunObserver* observer = nullptr;      // e.g. the live view; may be null
};

struct RunResult {
  int exit_code = kExitOk;
  std::string message;          // what ended the run when not a clean finish
  nlohmann::json summary;       // as written to summary.json
  double wall_time_s = 0;
  uint64_t exchanges = 0;       // TickBegin/TickEnd round trips
};

// "chainsim: <message>" on stderr unless options.quiet
void say(const RunOptions& options, const std::string& message);

}  // namespace chainsim
