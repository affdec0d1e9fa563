// Two fits at once on one core (paired_runs.h): each task gets, run for run,
// the bytes it would get alone; only one task's code runs at a time; a
// task's exception reaches the caller; nested tasks pair only in the last
// task left; each thread counts its own model runs.
#include "analysis/calibration/paired_runs.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
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
  std::vector<std::function<void()>> tasks;
  for (size_t i = 0; i < plan.size(); ++i)
    tasks.push_back([&, i] {
      for (const auto& [bench, rows] : plan[i]) got[i].push_back(paired_simulate(r.b[bench], r.t, r.sp, rows));
    });
  run_paired(tasks);
  for (size_t i = 0; i < plan.size(); ++i) {
    ASSERT_EQ(got[i].size(), plan[i].size());
    for (size_t j = 0; j < plan[i].size(); ++j)
      expect_same(got[i][j], r.alone(plan[i][j].first, plan[i][j].second),
                  "task " + std::to_string(i) + " run " + std::to_string(j));
  }
}

TEST(PairedRuns, OneTaskRunsAtATimeOnThreadsOfTheirOwn) {
  const Runs r;
  std::atomic<int> inside{0}, most{0};
  std::set<std::thread::id> threads;
  std::vector<std::function<void()>> tasks;
  for (size_t i = 0; i < 4; ++i)
    tasks.push_back([&, i] {
      for (size_t j = 0; j < 3 + i; ++j) {
        const int now = ++inside;
        most = std::max(most.load(), now);
        threads.insert(std::this_thread::get_id());
        std::this_thread::sleep_for(std::chrono::microseconds(200));   // time for another to come in
        --inside;
        paired_simulate(r.b[i], r.t, r.sp, 300);
      }
    });
  run_paired(tasks);
  EXPECT_EQ(most.load(), 1);
  EXPECT_EQ(threads.size(), 2u);
  EXPECT_EQ(threads.count(std::this_thread::get_id()), 0u);
}

TEST(PairedRuns, ATasksExceptionReachesTheCallerAndNoFurtherTaskStarts) {
  const Runs r;
  bool third = false;
  int second_runs = 0;
  std::vector<std::function<void()>> tasks = {
      [&] {
        paired_simulate(r.b[0], r.t, r.sp, 200);
        paired_simulate(r.b[1], r.t, r.sp, 200);
        throw std::runtime_error("task 0 fails");
      },
      [&] {
        for (int j = 0; j < 5; ++j) paired_simulate(r.b[2], r.t, r.sp, 200), ++second_runs;
      },
      [&] { third = true; },
  };
  try {
    run_paired(tasks);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "task 0 fails");
  }
  EXPECT_EQ(second_runs, 5);   // the other task ran to its end, alone after the failure
  EXPECT_FALSE(third);
  // a run's own error reaches its task, and the caller
  const std::vector<double> none;
  EXPECT_THROW(run_paired({[&] { paired_simulate(r.b[0], none, none, 10); },
                           [&] { paired_simulate(r.b[1], r.t, r.sp, 10); }}),
               std::invalid_argument);
}

TEST(PairedRuns, NestedTasksPairOnceTheOtherTaskHasEnded) {
  const Runs r;
  // nested tasks: their threads, and their runs against the bench alone
  auto nested = [&](std::set<std::thread::id>* ids) {
    std::vector<std::vector<BenchSample>> got(3);
    run_paired_each(3, [&](size_t k) {
      ids->insert(std::this_thread::get_id());
      got[k] = paired_simulate(r.b[k + 1], r.t, r.sp, 400 + 100 * k);
    });
    for (size_t k = 0; k < 3; ++k) expect_same(got[k], r.alone(k + 1, 400 + 100 * k), "nested " + std::to_string(k));
  };
  std::thread::id first_thread, second_thread;
  std::set<std::thread::id> early, late;
  run_paired({[&] {
                first_thread = std::this_thread::get_id();
                nested(&early);   // the other task still runs: one after the other, here
                paired_simulate(r.b[0], r.t, r.sp, 300);
              },
              [&] {
                second_thread = std::this_thread::get_id();
                // more runs than the first task's four: it has ended by the last
                for (int j = 0; j < 6; ++j) paired_simulate(r.b[5], r.t, r.sp, 300);
                nested(&late);   // the last task left: a pair of its own
              }});
  EXPECT_EQ(early, std::set<std::thread::id>{first_thread});
  EXPECT_EQ(late.size(), 2u);
  EXPECT_EQ(late.count(second_thread), 0u);

  // nested tasks begun while the other task runs, which then ends: the
  // first here, the rest as a pair of their own
  std::thread::id here;
  std::vector<std::thread::id> where(5);
  std::vector<std::vector<BenchSample>> got(5);
  run_paired({[&] { paired_simulate(r.b[0], r.t, r.sp, 300); },
              [&] {
                here = std::this_thread::get_id();
                run_paired_each(5, [&](size_t k) {
                  where[k] = std::this_thread::get_id();
                  got[k] = paired_simulate(r.b[k], r.t, r.sp, 200 + 50 * k);
                });
              }});
  EXPECT_EQ(where[0], here);
  EXPECT_NE(where[4], here);
  EXPECT_EQ(std::set<std::thread::id>(where.begin(), where.end()).size(), 3u);
  for (size_t k = 0; k < 5; ++k) expect_same(got[k], r.alone(k, 200 + 50 * k), "begun paired " + std::to_string(k));
}

// a task's runs are its own, its nested tasks' included (on threads of their
// own when it is the last task left); the caller's count gains them all
TEST(PairedRuns, ATaskCountsItsOwnModelRunsAndItsNestedTasks) {
  const BenchConfig ds = test_datasheet();
  const FitProblem p = make_fit_problem(ds, bench_record(ds, 5));
  std::vector<int> own(2, -1);
  const int here_before = thread_model_runs();
  run_paired_each(2, [&](size_t i) {
    const int before = thread_model_runs();
    for (size_t j = 0; j < 2 + 3 * i; ++j) run_model(p, p.datasheet, 500);
    // nested: one after the other while the other task runs, else a pair
    run_paired_each(2, [&](size_t k) {
      for (size_t j = 0; j <= k; ++j) run_model(p, p.datasheet, 300);
    });
    own[i] = thread_model_runs() - before;
  });
  EXPECT_EQ(own[0], 2 + 3);
  EXPECT_EQ(own[1], 5 + 3);
  EXPECT_EQ(thread_model_runs(), here_before + 13);
  run_model(p, p.datasheet, 10);
  EXPECT_EQ(thread_model_runs(), here_before + 14);
}

}  // namespace
}  // namespace chainsim
