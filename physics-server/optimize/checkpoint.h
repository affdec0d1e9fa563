// The search's state after a generation, written atomically (a temporary
// file renamed over the old one) so that a kill at any moment leaves the last
// complete generation: the population pagmo evolves, the cache's keys, how
// much of history.csv belongs to it, the best so far. --resume starts from it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct BestSoFar {
  bool valid = false;
  int generation = 0;
  int island = 0;
  size_t individual = 0;
  std::string key;
  std::vector<int64_t> genes;
  double fitness = 0;
  bool failed = true;
};

struct Checkpoint {
  std::string fingerprint;                     // of the problem, base scene, seed and population
  int generation = -1;                         // the last one every island completed (0: the initial population)
  struct Island {
    std::vector<std::vector<int64_t>> genes;   // the population after `generation`, in pagmo's order
    std::vector<double> f;                     // pagmo's fitness (minimised) of each
  };
  std::vector<Island> islands;
  int trials = 0;                              // runs per individual from generation 1 on (0: not decided yet)
  std::string trials_note;                     // trials: auto's decision, in words
  std::vector<std::string> cache_keys;
  uint64_t history_bytes = 0;
  BestSoFar best;
  uint64_t evaluations = 0, simulations = 0, cache_hits = 0;
};

// writes path atomically; throws CheckpointError
void write_checkpoint(const std::string& path, const Checkpoint& c);
// throws CheckpointError naming the file
Checkpoint read_checkpoint(const std::string& path);

}  // namespace chainsim
