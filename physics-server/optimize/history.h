// history.csv: one row per individual of every generation, in generation,
// island and index order: generation, island, individual, genome, fitness,
// the trials and their fitness's spread (sd, min, max), the measures, the
// fault or broken constraint, the early stop, whether the cache answered,
// wall seconds.
// Everything but wall_s is the same for the same problem and seed, whatever
// the workers or ranks and whether the search was resumed.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "optimize/evaluation.h"

namespace chainsim {

struct HistoryRow {
  int generation = 0;
  int island = 0;
  size_t individual = 0;
  std::string genome;        // the individual's key
  EvalResult result;
  bool cached = false;       // answered by the cache, not simulated in this row
};

// "generation,island,individual,genome,fitness,trials,fitness_sd,fitness_min,fitness_max,<measures>,fault,early_stop,cached,wall_s"
std::string history_header(const std::vector<std::string>& measure_names);
std::string history_line(const HistoryRow& row);
// a CSV field, quoted when it needs to be
std::string csv_field(const std::string& s);
// a number as history writes it: %.10g, "inf", "-inf", "" for NaN
std::string history_number(double v);

// the rows of a history file's text; throws std::runtime_error naming source:line
std::vector<HistoryRow> parse_history(const std::string& text, size_t n_measures, const std::string& source);

class HistoryFile {
 public:
  // creates the file with its header, or (resume) opens it and cuts it to
  // keep_bytes: the rows of the generations the checkpoint holds (a file
  // with another header, from an older chainsim, is an error)
  HistoryFile(const std::string& path, const std::vector<std::string>& measure_names, bool resume,
              uint64_t keep_bytes);
  ~HistoryFile();
  HistoryFile(const HistoryFile&) = delete;
  HistoryFile& operator=(const HistoryFile&) = delete;
  void append(const HistoryRow& row);
  // flushes; returns the file's size in bytes
  uint64_t flush();

 private:
  std::string path_;
  FILE* f_ = nullptr;
};

}  // namespace chainsim
