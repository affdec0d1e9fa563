// What a search keeps on disk: the evaluation journal and cache, the
// checkpoint, history.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <fstream>
#include <limits>
#include <sstream>

#include "optimize/checkpoint.h"
#include "optimize/eval_cache.h"
#include "optimize/history.h"
#include "temp_dir.h"

using namespace chainsim;

namespace {

// a new directory per call, all removed when the test program ends
std::string fresh_dir() {
  static std::deque<chainsim_test::TempDir> dirs;
  return dirs.emplace_back("chainsim-store-test").path.string();
}

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

EvalResult result(double f, bool failed = false, const std::string& why = "") {
  EvalResult r;
  r.fitness = f;
  r.measures = {f / 2, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()};
  r.failed = failed;
  r.why = why;
  r.wall_s = 1.25;
  return r;
}

}  // namespace

TEST(EvalResultJson, RoundTripsNonFiniteNumbers) {
  const EvalResult r = result(0.1 + 0.2, true, "module 1 (rotation) closed its socket");
  EXPECT_EQ(eval_result_from_json(nlohmann::json::parse(eval_result_to_json(r).dump())), r);
  EvalResult spread = result(2.0);
  spread.trials = 3;
  spread.fitness_sd = 0.25;
  spread.fitness_min = 1.75;
  spread.fitness_max = 2.5;
  spread.early_stop = "early stop at 3.000 s: the head got 0.1 mm further in the last 2 s";
  EXPECT_EQ(eval_result_from_json(nlohmann::json::parse(eval_result_to_json(spread).dump())), spread);
  EXPECT_EQ(trial_seed(42, 0), 42u);  // one run per individual: its own seed
  EXPECT_NE(trial_seed(42, 1), trial_seed(42, 2));
  EXPECT_EQ(trial_seed(42, 1), trial_seed(42, 1));
  EXPECT_NE(trial_seed(42, kFreshTrial), trial_seed(42, 1));  // verification's seeds are not the search's
  EXPECT_EQ(deterministic_fault_text("module 1 (rotation, pid 4242) closed its socket (signal 11)"),
            "module 1 (rotation) closed its socket (signal 11)");
}

TEST(EvalCache, TheJournalKeepsResultsAcrossProcesses) {
  const std::string j = fresh_dir() + "/evaluations.jsonl";
  {
    EvalCache c(j, "fp");
    c.record("THRH", result(1.5));
    c.record("TRRH", result(2.5, true, "constraint: x = 0 < 1"));
    EXPECT_EQ(c.find("THRH"), nullptr);  // journaled, not yet in the cache proper
    ASSERT_NE(c.journaled("THRH"), nullptr);
    c.commit("THRH");
    ASSERT_NE(c.find("THRH"), nullptr);
    EXPECT_EQ(c.keys(), (std::vector<std::string>{"THRH"}));
  }
  EvalCache c(j, "fp");  // as after a kill: everything journaled is known, the cache proper is empty
  EXPECT_EQ(c.size(), 0u);
  ASSERT_NE(c.journaled("TRRH"), nullptr);
  EXPECT_EQ(*c.journaled("TRRH"), result(2.5, true, "constraint: x = 0 < 1"));
  c.restore({"THRH", "TRRH"});
  EXPECT_EQ(*c.find("THRH"), result(1.5));
  EXPECT_THROW(c.restore({"THHH"}), CacheError);
}

TEST(EvalCache, ATornLastLineIsDroppedADamagedOneIsAnError) {
  const std::string d = fresh_dir();
  {
    EvalCache c(d + "/a.jsonl", "fp");
    c.record("A", result(1));
  }
  { std::ofstream(d + "/a.jsonl", std::ios::app) << R"({"key": "B", "resu)"; }
  {
    EvalCache c(d + "/a.jsonl", "fp");
    EXPECT_NE(c.journaled("A"), nullptr);
    EXPECT_EQ(c.journaled("B"), nullptr);
    c.record("C", result(3));
  }
  EvalCache again(d + "/a.jsonl", "fp");  // the torn line was cut off, C starts clean
  EXPECT_NE(again.journaled("C"), nullptr);
  try {
    EvalCache other(d + "/a.jsonl", "another search");
    FAIL();
  } catch (const CacheError& e) {
    EXPECT_NE(std::string(e.what()).find("the evaluations of another search"), std::string::npos) << e.what();
  }

  std::ofstream(d + "/b.jsonl") << "{\"key\": \"A\"}\n" << eval_result_to_json(result(1)).dump() << "\n";
  try {
    EvalCache bad(d + "/b.jsonl", "fp");
    FAIL();
  } catch (const CacheError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(d + "/b.jsonl:1: not a journal line", 0), 0u) << e.what();
  }
}

TEST(Checkpoint, RoundTripsExactly) {
  const std::string p = fresh_dir() + "/checkpoint.json";
  Checkpoint c;
  c.fingerprint = "abc";
  c.generation = 7;
  c.islands = {{{{1, 0, 3}, {0, 2, 1}}, {-0.1 - 0.2, 1.0 / 3.0}},  // values that need all 17 digits
               {{{2, 2, 2}}, {HUGE_VAL}}};                       // and one JSON has no number for
  c.trials = 3;
  c.cache_keys = {"TRRH", "THRH"};
  c.history_bytes = 12345;
  c.best = {true, 5, 1, 3, "THRH", {1, 0, 3}, 0.30000000000000004, false};
  c.evaluations = 320;
  c.simulations = 100;
  c.cache_hits = 220;
  write_checkpoint(p, c);
  const Checkpoint r = read_checkpoint(p);
  EXPECT_EQ(r.fingerprint, c.fingerprint);
  EXPECT_EQ(r.generation, 7);
  ASSERT_EQ(r.islands.size(), 2u);
  EXPECT_EQ(r.islands[0].genes, c.islands[0].genes);
  EXPECT_EQ(r.islands[0].f, c.islands[0].f);
  EXPECT_EQ(r.islands[1].f, c.islands[1].f);
  EXPECT_EQ(r.trials, 3);
  EXPECT_EQ(r.best.island, 1);
  EXPECT_EQ(r.cache_keys, c.cache_keys);
  EXPECT_EQ(r.history_bytes, 12345u);
  EXPECT_EQ(r.best.key, "THRH");
  EXPECT_EQ(r.best.fitness, 0.30000000000000004);
  EXPECT_EQ(r.best.genes, c.best.genes);
  EXPECT_EQ(r.cache_hits, 220u);
  std::ofstream(p) << "{\"format\": 1, \"generation\": 3}";
  try {
    read_checkpoint(p);
    FAIL() << "a format-1 checkpoint was read";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("older chainsim"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_checkpoint(p + ".missing"), CheckpointError);
}

TEST(History, RowsRoundTripAndAResumeCutsToTheCheckpoint) {
  const std::string p = fresh_dir() + "/history.csv";
  uint64_t after_gen0 = 0;
  {
    HistoryFile h(p, {"x", "t", "n"}, false, 0);
    EvalResult spread = result(1.5);
    spread.trials = 3;
    spread.fitness_sd = 0.125;
    spread.fitness_min = 1.25;
    spread.fitness_max = 1.75;
    spread.early_stop = "early stop at 2.000 s: the head got 0.0 mm further in the last 2 s";
    h.append({0, 0, 0, "THRH central.bend_ms=1500", spread, false});
    h.append({0, 0, 1, "TRRH", result(0, true, "module 1 (rotation) said \"no\", twice"), false});
    after_gen0 = h.flush();
    h.append({1, 1, 0, "THRH central.bend_ms=1500", result(1.5), true});
    h.flush();
  }
  const std::string text = slurp(p);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "generation,island,individual,genome,fitness,trials,fitness_sd,fitness_min,fitness_max,x,t,n,fault,"
            "early_stop,cached,wall_s");
  EXPECT_NE(text.find("0,0,1,TRRH,0,1,,,,0,inf,,\"module 1 (rotation) said \"\"no\"\", twice\",,no,1.250\n"),
            std::string::npos)
      << text;
  const auto rows = parse_history(text, 3, p);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].result.trials, 3);
  EXPECT_EQ(rows[0].result.fitness_sd, 0.125);
  EXPECT_EQ(rows[0].result.fitness_max, 1.75);
  EXPECT_FALSE(rows[0].result.failed);  // an early stop is no failure
  EXPECT_EQ(rows[0].result.early_stop, "early stop at 2.000 s: the head got 0.0 mm further in the last 2 s");
  EXPECT_EQ(rows[2].island, 1);
  EXPECT_EQ(rows[1].result.why, "module 1 (rotation) said \"no\", twice");
  EXPECT_TRUE(rows[1].result.failed);
  EXPECT_TRUE(std::isinf(rows[1].result.measures[1]));
  EXPECT_TRUE(std::isnan(rows[1].result.measures[2]));
  EXPECT_TRUE(rows[2].cached);
  {
    HistoryFile h(p, {"x", "t", "n"}, true, after_gen0);  // resume from generation 0's checkpoint
    h.append({1, 0, 0, "TRRH", result(2), false});
    h.flush();
  }
  const auto resumed = parse_history(slurp(p), 3, p);
  ASSERT_EQ(resumed.size(), 3u);
  EXPECT_EQ(resumed[2].genome, "TRRH");
  EXPECT_THROW(parse_history("h\n1,2,3\n", 3, p), std::runtime_error);
  // a history of another layout (an older chainsim) is not resumed into
  std::ofstream(p) << "generation,individual,genome,fitness,x,t,n,fault,cached,wall_s\n0,0,TRRH,1,1,1,1,,no,0.1\n";
  EXPECT_THROW(HistoryFile(p, {"x", "t", "n"}, true, 10), std::runtime_error);
}
