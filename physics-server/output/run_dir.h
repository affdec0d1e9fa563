// The run directory checked before a run starts: `chainsim run --out DIR` that
// cannot be written is a bad option (exit 1) naming the path, found before any
// module process starts rather than as an internal error on the first write.
#pragma once

#include <string>

namespace chainsim {

struct RunDirCheck {
  std::string error;    // empty when dir can be written; else "--out 'DIR': what"
  bool had_run = false; // dir already held a run (trace.csv or summary.json): it is replaced
};

// creates dir (and its parents) if missing, and checks that it is a directory
// in which a file can be created and written
RunDirCheck prepare_run_dir(const std::string& dir);

}  // namespace chainsim
