// A search's winners, checked before anyone trusts them: the leaders of a
// history (the best distinct individuals), whether their ranking is within
// the noise of their trials, and verification: each leader run again with
// fresh seeds the search never used, with the converged solver, and on the
// board's own binaries, with a flag wherever a verdict (pass or fail) flips.
// The verified best is the best with fresh seeds, not the luckiest in the
// search (docs/optimize.md, "Verification").
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimize/evaluator_pool.h"
#include "optimize/history.h"
#include "optimize/problem.h"

namespace chainsim {

// the k best distinct individuals of a history, best first: the ones that
// did not fail before those that did, then by fitness (the first row of a
// genome stands for it; ties keep history order)
std::vector<HistoryRow> leaders(const Problem& pr, const std::vector<HistoryRow>& rows, size_t k);

// "" or, when the leaders' fitnesses are closer than their trials can tell
// apart, a sentence: "the ranking of the top 3 is within the noise ...; raise
// evaluation.trials". Leader k is within the noise of the best when their
// difference is under twice its standard error (from the trials' sd). With
// one trial per individual and no spread known, says so when the problem
// fixed trials at 1.
std::string noise_warning(const Problem& pr, const std::vector<HistoryRow>& leaders);

struct VerifySettings {
  int top = 3;          // leaders to verify
  int trials = 0;       // fresh trials each; 0: the search's trials, at least 3
  bool exact = true;    // also with physics.solver: exact
  bool pic = false;     // also on the board's binaries (--target pic), one trial
};

struct VerifiedLeader {
  HistoryRow search;            // its row in the search
  EvalResult fresh;             // fresh seeds (trials kFreshTrial ..)
  bool has_exact = false, has_pic = false;
  EvalResult exact, pic;
  std::vector<std::string> flags;  // verdicts that flip, in words
};

struct Verification {
  std::vector<VerifiedLeader> leaders;  // in the search's order
  int best = -1;                        // the verified best: index into leaders (-1: none passed)
  int fresh_trials = 0;
};

// the tasks and their results; false when interrupted
bool verify_leaders(const Problem& pr, const std::vector<HistoryRow>& leaders, const VerifySettings& settings,
                    EvaluatorPool& pool, Verification* out, bool quiet);

// the flags of one leader (exposed for tests)
std::vector<std::string> verdict_flags(const VerifiedLeader& v);

// verify.csv: a row per leader; verify.json: the same and the verified best
std::string verification_csv(const Verification& v);
nlohmann::json verification_json(const Verification& v);

}  // namespace chainsim
