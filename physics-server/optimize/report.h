// report.html: one self-contained page about a search: best / mean / worst
// fitness per generation (as the paper's Fig. 11 and 13), the per-generation
// figures, the best individuals, and the best run's replay (the viewer's own
// page, which the caller makes, embedded as it is).
#pragma once

#include <string>
#include <vector>

#include "optimize/checkpoint.h"
#include "optimize/history.h"
#include "optimize/problem.h"

namespace chainsim {

struct GenerationStats {
  int generation = 0;
  double best = 0, mean = 0, worst = 0;  // over the generation's individuals, in the objective's sense
  double best_so_far = 0;
  int individuals = 0, failed = 0, cached = 0;
  double wall_s = 0;                     // summed over the simulated ones
};

// per-generation figures of a history, in generation order
std::vector<GenerationStats> generation_stats(const Problem& pr, const std::vector<HistoryRow>& rows);

struct Verification;

// what the page says beside the history
struct ReportNotes {
  std::string replay;        // a sentence about the best's re-run
  std::string trials;        // trials: auto's decision
  std::string noise;         // noise_warning's sentence, or empty
  const Verification* verification = nullptr;  // the winners' verification, if run
  std::string verification_note;                // why it was not (complete), or empty
};

// the page; replay_html is the viewer's page of the best run (empty: none)
std::string report_html(const Problem& pr, const std::vector<HistoryRow>& rows, const BestSoFar& best,
                        const ReportNotes& notes, const std::string& replay_html);

}  // namespace chainsim
