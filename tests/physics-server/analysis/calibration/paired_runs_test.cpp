// Two fits at once on one core (paired_runs.h): a batch gives each run the
// bytes it would get alone, and so does a task, run for run; the tasks run
// on the caller's thread, one at a time; a task's exception reaches the
// caller; nested tasks pair only in the last task left; each task counts its
// own model runs.
#include "analysis/calibration/paired_runs.h"

#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "analysis/calibration/servo_fit.h"
#include "bench_record.h"

namespace chainsim {
namespace {

struct Runs {
  std::vector<double> t, sp;
  std::vector<BenchConfig> b;
  Runs() {
    const MeasuredRecord m = bench_record(test_datasheet(), 3);
    t.assign(m.t.begin(), m.t.begin() + 1200);
    sp.assign(m.sp.begin(), m.sp.begin() + 1200);
    for (int i = 0; i < 6; ++i) {
      BenchConfig c = test_datasheet();
      c.dt_us = 100;
      c.servo.kp *= 1 + 0.05 * i;
      if (i % 3 == 1) c.servo.pwm_frame_s = 0.02, c.servo.pwm_frame_phase_s = 0.001 * i;
      if (i % 3 == 2) c.servo.coulomb_nm = 0.002 * i, c.servo.backlash_deg = 1;
      b.push_back(c);
    }
  }
  // the bench alone, as simulate_bench gives it
  std::vector<BenchSample> alone(size_t i, size_t rows) const {
    return simulate_bench(b[i], t, sp, BenchSolver::closed_form, rows);
  }
};

void expect_same(const std::vector<BenchSample>& got, const std::vector<BenchSample>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t k = 0; k < want.size(); ++k) {
    ASSERT_EQ(got[k].angle_deg, want[k].angle_deg) << what << " sample " << k;
    ASSERT_EQ(got[k].current_a, want[k].current_a) << what << " sample " << k;
  }
}

TEST(PairedRuns, EachTaskGetsTheRunsItWouldGetAlone) {
  const Runs r;
  // per task: (bench, rows) of its runs, in order; the tasks have different
  // numbers of runs, so one goes on alone, and the rows differ within a pair
  const std::vector<std::vector<std::pair<size_t, size_t>>> plan = {
      {{0, 1200}, {1, 700}, {2, 1200}, {3, 5}},
      {{4, 1200}},
      {{5, 900}, {0, 1200}, {2, 1}, {1, 1200}, {3, 1200}, {4, 600}, {5, 1200}},
  };
  std::vector<std::vector<std::vector<BenchSample>>> got(plan.size());
  std::vector<std::function<void(ModelRuns&)>> tasks;
  for (size_t i = 0; i < plan.size(); ++i)
    tasks.push_back([&, i](ModelRuns& runs) {
      for (const auto& [bench, rows] : plan[i]) got[i].push_back(runs.simulate(r.b[bench], r.t, r.sp, rows));
    });
  ModelRuns runs;
  run_paired(runs, tasks);
  for (size_t i = 0; i < plan.size(); ++i) {
    ASSERT_EQ(got[i].size(), plan[i].size());
    for (size_t j = 0; j < plan[i].size(); ++j)
      expect_same(got[i][j], r.alone(plan[i][j].first, plan[i][j].second),
                  "task " + std::to_string(i) + " run " + std::to_string(j));
  }
}

// simulate these runs: each as simulate_bench gives it alone, those on the
// same set-points stepped together, a group's error its own
TEST(PairedRuns, ABatchGivesEachRunItsOwnBytes) {
  const Runs r;
  const std::vector<double> t2(r.t.begin(), r.t.begin() + 800), sp2(r.sp.begin(), r.sp.begin() + 800);
  const std::vector<double> none;
  const std::vector<RunRequest> batch = {{&r.b[0], &r.t, &r.sp, 1200}, {&r.b[1], &t2, &sp2, 800},
                                         {&r.b[2], &r.t, &r.sp, 300},  {&r.b[3], &none, &none, 10},
                                         {&r.b[4], &r.t, &r.sp, 1200}};
  PairedRunStats stats;
  const std::vector<BatchResult> got = simulate_batch(batch, &stats);
  ASSERT_EQ(got.size(), batch.size());
  for (size_t i : {0, 2, 4}) {
    EXPECT_FALSE(got[i].error);
    expect_same(got[i].samples, r.alone(i, batch[i].rows), "run " + std::to_string(i));
  }
  EXPECT_FALSE(got[1].error);
  expect_same(got[1].samples, simulate_bench(r.b[1], t2, sp2, BenchSolver::closed_form, 800), "run 1");
  EXPECT_TRUE(got[3].error);
  EXPECT_THROW(std::rethrow_exception(got[3].error), std::invalid_argument);
  // three groups: the three runs on the whole record, the shorter one, the empty one
  EXPECT_EQ(stats.groups, 3);
  EXPECT_EQ(stats.runs_together, 3);
}

// the tasks run on the caller's thread, one at a time, and their runs are
// stepped two at a time
TEST(PairedRuns, OneTaskRunsAtATimeOnTheCallersThread) {
  const Runs r;
  int inside = 0, most = 0;
  std::set<std::thread::id> threads;
  std::vector<std::function<void(ModelRuns&)>> tasks;
  for (size_t i = 0; i < 4; ++i)
    tasks.push_back([&, i](ModelRuns& runs) {
      for (size_t j = 0; j < 3 + i; ++j) {
        const int now = ++inside;
        most = std::max(most, now);
        threads.insert(std::this_thread::get_id());
        --inside;
        runs.simulate(r.b[i], r.t, r.sp, 300);
      }
    });
  ModelRuns runs;
  run_paired(runs, tasks);
  EXPECT_EQ(most, 1);
  EXPECT_EQ(threads, std::set<std::thread::id>{std::this_thread::get_id()});
  // 18 runs: 3 + 4 + 5 + 6, the last task's final ones alone
  const PairedRunStats after = runs.stats();
  EXPECT_GE(after.runs_together, 12);
  EXPECT_EQ(after.groups, 18 - after.runs_together / 2);
  EXPECT_EQ(runs.count(), 18);
}

TEST(PairedRuns, ATasksExceptionReachesTheCallerAndNoFurtherTaskStarts) {
  const Runs r;
  bool third = false;
  int second_runs = 0;
  std::vector<std::function<void(ModelRuns&)>> tasks = {
      [&](ModelRuns& runs) {
        runs.simulate(r.b[0], r.t, r.sp, 200);
        runs.simulate(r.b[1], r.t, r.sp, 200);
        throw std::runtime_error("task 0 fails");
      },
      [&](ModelRuns& runs) {
        for (int j = 0; j < 5; ++j) runs.simulate(r.b[2], r.t, r.sp, 200), ++second_runs;
      },
      [&](ModelRuns&) { third = true; },
  };
  ModelRuns runs;
  try {
    run_paired(runs, tasks);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "task 0 fails");
  }
  EXPECT_EQ(second_runs, 5);   // the other task ran to its end, alone after the failure
  EXPECT_FALSE(third);
  // a run's own error reaches its task, and the caller
  const std::vector<double> none;
  EXPECT_THROW(run_paired(runs, {[&](ModelRuns& runs) { runs.simulate(r.b[0], none, none, 10); },
                                 [&](ModelRuns& runs) { runs.simulate(r.b[1], r.t, r.sp, 10); }}),
               std::invalid_argument);
}

TEST(PairedRuns, NestedTasksPairOnceTheOtherTaskHasEnded) {
  const Runs r;
  // nested tasks: when each begins and ends (k, -1 - k), and their runs
  // against the bench alone
  auto nested = [&](ModelRuns& runs, std::vector<int>* events) {
    std::vector<std::vector<BenchSample>> got(3);
    run_paired_each(runs, 3, [&](ModelRuns& runs, size_t k) {
      events->push_back(static_cast<int>(k));
      got[k] = runs.simulate(r.b[k + 1], r.t, r.sp, 400 + 100 * k);
      events->push_back(-1 - static_cast<int>(k));
    });
    for (size_t k = 0; k < 3; ++k) expect_same(got[k], r.alone(k + 1, 400 + 100 * k), "nested " + std::to_string(k));
  };
  std::vector<int> early, late;
  ModelRuns runs;
  run_paired(runs, {[&](ModelRuns& runs) {
                      nested(runs, &early);   // the other task still runs: one after the other, here
                      runs.simulate(r.b[0], r.t, r.sp, 300);
                    },
                    [&](ModelRuns& runs) {
                      // more runs than the first task's four: it has ended by the last
                      for (int j = 0; j < 6; ++j) runs.simulate(r.b[5], r.t, r.sp, 300);
                      nested(runs, &late);   // the last task left: a pair of its own
                    }});
  EXPECT_EQ(early, (std::vector<int>{0, -1, 1, -2, 2, -3}));
  ASSERT_EQ(late.size(), 6u);
  EXPECT_EQ(late[0], 0);
  EXPECT_EQ(late[1], 1);   // begun before the first ended

  // nested tasks begun while the other task runs, which then ends: the
  // first one after the other, the rest as a pair of their own
  std::vector<int> events;
  std::vector<std::vector<BenchSample>> got(5);
  run_paired(runs, {[&](ModelRuns& runs) { runs.simulate(r.b[0], r.t, r.sp, 300); },
                    [&](ModelRuns& runs) {
                      run_paired_each(runs, 5, [&](ModelRuns& runs, size_t k) {
                        events.push_back(static_cast<int>(k));
                        got[k] = runs.simulate(r.b[k], r.t, r.sp, 200 + 50 * k);
                        events.push_back(-1 - static_cast<int>(k));
                      });
                    }});
  ASSERT_EQ(events.size(), 10u);
  EXPECT_EQ(events[0], 0);
  EXPECT_EQ(events[1], -1);
  EXPECT_EQ(events[2], 1);
  EXPECT_EQ(events[3], 2);   // paired
  for (size_t k = 0; k < 5; ++k) expect_same(got[k], r.alone(k, 200 + 50 * k), "begun paired " + std::to_string(k));
}

// a task's runs are its own, its nested tasks' included (on workers of their
// own when it is the last task left); the caller's count gains them all
TEST(PairedRuns, ATaskCountsItsOwnModelRunsAndItsNestedTasks) {
  const BenchConfig ds = test_datasheet();
  const FitProblem p = make_fit_problem(ds, bench_record(ds, 5));
  std::vector<int> own(2, -1);
  ModelRuns runs;
  run_paired_each(runs, 2, [&](ModelRuns& runs, size_t i) {
    const int before = runs.count();
    for (size_t j = 0; j < 2 + 3 * i; ++j) run_model(runs, p, p.datasheet, 500);
    // nested: one after the other while the other task runs, else a pair
    run_paired_each(runs, 2, [&](ModelRuns& runs, size_t k) {
      for (size_t j = 0; j <= k; ++j) run_model(runs, p, p.datasheet, 300);
    });
    own[i] = runs.count() - before;
  });
  EXPECT_EQ(own[0], 2 + 3);
  EXPECT_EQ(own[1], 5 + 3);
  EXPECT_EQ(runs.count(), 13);
  run_model(runs, p, p.datasheet, 10);
  EXPECT_EQ(runs.count(), 14);
}

}  // namespace
}  // namespace chainsim
