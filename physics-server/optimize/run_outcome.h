// What a finished `chainsim run` left in its run directory, reduced to what
// the search's measures need: how it ended, the head's and the tail's tracks
// (trace.csv), the chain's displacement and energy (summary.json).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "output/run_reader.h"

namespace chainsim {

struct RunOutcome {
  bool finished = false;         // ran to its duration with no fault
  std::string fault;             // why not (the run's own words), empty when finished
  std::string early_stop;        // a stop_when rule ended it (summary.json's early_stop), else empty
  int modules = 0;
  double sim_time_s = 0;
  std::vector<double> t_s;                 // trace row times
  std::vector<Eigen::Vector3d> head, tail; // module 0's first body, the last module's last body, m
  Eigen::Vector3d chain_displacement = Eigen::Vector3d::Zero();  // summary: mass centre, end - start
  double energy_j = 0;           // summed over the modules
};

// reads run_dir/summary.json and run_dir/trace.csv through the run reader
// (output/run_reader.h), keeping only the trace's time and body positions;
// throws RunReadError naming the file when one is missing or malformed
RunOutcome read_run_outcome(const std::string& run_dir);

// the same from the files' text (tests); source names them in errors
RunOutcome parse_run_outcome(const std::string& summary_json, const std::string& trace_csv,
                           const std::string& source);

}  // namespace chainsim
