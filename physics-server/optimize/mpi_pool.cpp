#include "optimize/mpi_pool.h"

#include <mpi.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <list>
#include <map>
#include <set>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "optimize/problem.h"

namespace chainsim {

namespace {

using Clock = std::chrono::steady_clock;

enum Tag { kHello = 1, kTask = 2, kResult = 3, kBeat = 4, kPing = 5, kStop = 6 };

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string host_name() {
  char h[256] = {};
  gethostname(h, sizeof h - 1);
  return h;
}

// sends that must not block on a rank that may be dead: each buffer lives
// until its request completes (or forever, for a dead rank)
class Outbox {
 public:
  void send(int dest, int tag, const std::string& text) {
    sends_.push_back({text, MPI_REQUEST_NULL});
    Send& s = sends_.back();
    MPI_Isend(s.text.data(), static_cast<int>(s.text.size()), MPI_CHAR, dest, tag, MPI_COMM_WORLD, &s.request);
    tidy();
  }
  bool empty() const { return sends_.empty(); }
  void tidy() {
    for (auto it = sends_.begin(); it != sends_.end();) {
      int done = 0;
      MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
      it = done ? sends_.erase(it) : std::next(it);
    }
  }

 private:
  struct Send {
    std::string text;
    MPI_Request request;
  };
  std::list<Send> sends_;
};

// a waiting message, if any: (source, tag, text)
bool receive(int source, int* from, int* tag, std::string* text) {
  int flag = 0;
  MPI_Status st;
  if (MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st) != MPI_SUCCESS || !flag) return false;
  int n = 0;
  MPI_Get_count(&st, MPI_CHAR, &n);
  text->assign(static_cast<size_t>(n), '\0');
  MPI_Recv(text->data(), n, MPI_CHAR, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  *from = st.MPI_SOURCE;
  *tag = st.MPI_TAG;
  return true;
}

// a process of this host is gone (or a zombie nobody has reaped yet)
bool local_process_gone(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  if (!in) return true;
  std::string line;
  std::getline(in, line);
  const size_t p = line.rfind(')');
  return p == std::string::npos || p + 2 >= line.size() || line[p + 2] == 'Z' || line[p + 2] == 'X';
}

}  // namespace

bool launched_by_mpirun() {
  // mpirun (OpenMPI), a PMI launcher, or a PMIx one such as `srun --mpi=pmix`
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
}

MpiSession::MpiSession(int* argc, char*** argv) {
  MPI_Init(argc, argv);
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);  // a dead peer is an error code, not an abort
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() = default;

bool MpiSession::recovery_enabled() {
  const char* r = std::getenv("OMPI_MCA_orte_enable_recovery");
  const char* a = std::getenv("OMPI_MCA_orte_abort_on_non_zero_status");
  auto on = [](const char* v) { return v && (std::string(v) == "1" || std::string(v) == "true"); };
  auto off = [](const char* v) { return v && (std::string(v) == "0" || std::string(v) == "false"); };
  return on(r) && off(a);
}

bool MpiSession::exit_status_ignored() {
  const char* r = std::getenv("OMPI_MCA_orte_enable_recovery");
  const char* a = std::getenv("OMPI_MCA_orte_abort_on_non_zero_status");
  return (r && (std::string(r) == "1" || std::string(r) == "true")) || (a && (std::string(a) == "0" || std::string(a) == "false"));
}

void MpiSession::exit(int code, bool rank_lost, bool remote_lost) {
  std::fflush(stdout);
  std::fflush(stderr);
  // with --enable-recovery or orte_abort_on_non_zero_status 0, mpirun exits
  // 0 whatever its ranks exit with (MPI_Abort included: measured with
  // OpenMPI 4.1.4), so an unfinished search would look done. Ended by
  // SIGTERM, mpirun exits 1: rank 0, mpirun's own child on its node, does
  // that (a rank 0 started by an orted cannot, and says so).
  if (code != 0 && rank_ == 0 && exit_status_ignored()) {
    std::ifstream in("/proc/" + std::to_string(getppid()) + "/comm");
    std::string parent;
    std::getline(in, parent);
    if (parent == "mpirun" || parent == "mpiexec" || parent == "orterun") {
      std::fprintf(stderr, "optimize: the search did not finish (exit code %d): ending mpirun (pid %d) so that it "
                           "exits non-zero, which with --enable-recovery it would not\n", code, static_cast<int>(getppid()));
      std::fflush(stderr);
      kill(getppid(), SIGTERM);
      _exit(code);
    }
    std::fprintf(stderr, "optimize: the search did not finish (exit code %d), but mpirun, started with "
                         "--enable-recovery or orte_abort_on_non_zero_status 0, may exit 0\n", code);
  }
  // a host lost: measured with OpenMPI 4.1.4 and --enable-recovery, mpirun
  // then waited for ever in 7 of 34 tries; MPI_Abort ends it (exit status 0
  // for error code 0, about 8 s later)
  if (remote_lost && rank_ == 0) MPI_Abort(MPI_COMM_WORLD, code);
  if (rank_lost) _exit(code);  // MPI_Finalize may wait forever for the dead rank
  MPI_Finalize();
  std::exit(code);
}

struct MpiPool::Impl {
  struct Rank {
    int rank = 0;
    bool live = true;
    bool greeted = false;            // its hello came: pid, host and capacity known
    std::string host;
    pid_t pid = 0;
    int capacity = 1;
    std::set<uint64_t> holding;      // ids of the tasks it runs
    Clock::time_point last_heard = Clock::now();
    Clock::time_point last_ping = Clock::now();
  };
  std::vector<Rank> ranks;           // 1..size-1
  double timeout_s = 30;
  bool quiet = false;
  int lost = 0;
  Clock::time_point started = Clock::now();
  std::map<uint64_t, EvalTask> tasks;  // submitted, not yet handed back
  std::deque<uint64_t> queue;          // not yet given to a rank
  std::string my_host = host_name();
  Outbox out;

  std::string name(const Rank& r) const {
    std::string n = "rank " + std::to_string(r.rank);
    if (r.pid) n += " (pid " + std::to_string(r.pid) + " on " + r.host + ")";
    return n;
  }
};

MpiPool::MpiPool(int size, double rank_timeout_s, bool quiet) : impl_(std::make_unique<Impl>()) {
  impl_->timeout_s = rank_timeout_s;
  impl_->quiet = quiet;
  for (int r = 1; r < size; ++r) {
    Impl::Rank k;
    k.rank = r;
    impl_->ranks.push_back(k);
  }
}

MpiPool::~MpiPool() = default;

int MpiPool::parallelism() const {
  int n = 0;
  for (const auto& r : impl_->ranks) n += r.live ? r.capacity : 0;
  return n;
}

std::string MpiPool::describe() const {
  int live = 0;
  for (const auto& r : impl_->ranks) live += r.live;
  return std::to_string(live) + " MPI worker rank" + (live == 1 ? "" : "s");
}

int MpiPool::lost_ranks() const { return impl_->lost; }

int MpiPool::lost_remote_ranks() const {
  int n = 0;
  for (const auto& r : impl_->ranks) n += !r.live && r.host != impl_->my_host;
  return n;
}

void MpiPool::stop_workers(bool finalize) {
  // also to ranks given up: one that was only slow is still waiting for work
  for (auto& r : impl_->ranks) impl_->out.send(r.rank, kStop, finalize && r.live ? "finalize" : "exit");
  // let the messages leave before this rank does (sends to a dead rank never complete)
  const auto t0 = Clock::now();
  while (!impl_->out.empty() && since(t0) < 1.0) {
    impl_->out.tidy();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void MpiPool::submit(uint64_t id, const EvalTask& task) {
  impl_->tasks[id] = task;
  impl_->queue.push_back(id);
}

size_t MpiPool::pending() const { return impl_->tasks.size(); }

bool MpiPool::poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) {
  Impl& I = *impl_;
  const auto until = Clock::now() + std::chrono::duration<double>(wait_s);
  auto by_rank = [&](int rank) -> Impl::Rank* {
    return rank >= 1 && rank <= static_cast<int>(I.ranks.size()) ? &I.ranks[static_cast<size_t>(rank - 1)] : nullptr;
  };
  const size_t done_before = done->size();
  for (;;) {
    if (interrupt_signal()) return false;
    bool busy = false;
    // hand out work
    for (auto& r : I.ranks) {
      // only to a rank that said hello: one that dies holding work is then
      // known by its pid (a rank killed before its hello could be found
      // only by the silence timeout)
      while (r.live && r.greeted && !I.queue.empty() && static_cast<int>(r.holding.size()) < r.capacity) {
        const uint64_t id = I.queue.front();
        I.queue.pop_front();
        const EvalTask& t = I.tasks.at(id);
        const nlohmann::json j = {{"id", id},           {"chain", t.phenotype.chain}, {"values", t.phenotype.values},
                                  {"key", t.key},       {"seed", t.seed},             {"trials", t.trials},
                                  {"first_trial", t.first_trial}, {"solver", t.solver}, {"target", t.target},
                                  {"index", t.index}};
        I.out.send(r.rank, kTask, j.dump());
        if (r.holding.empty()) r.last_heard = Clock::now();  // its silence counts from now
        r.holding.insert(id);
        busy = true;
      }
    }
    // what came back
    int from = 0, tag = 0;
    std::string text;
    while (receive(MPI_ANY_SOURCE, &from, &tag, &text)) {
      busy = true;
      Impl::Rank* r = by_rank(from);
      if (!r || !r->live) continue;  // a rank given up stays given up
      r->last_heard = Clock::now();
      if (tag == kHello) {
        const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
        if (j.is_object()) {
          r->host = j.value("host", "");
          r->pid = j.value("pid", 0);
          r->greeted = true;
          r->capacity = std::max(1, j.value("workers", 1));
        }
      } else if (tag == kResult) {
        const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
        if (!j.is_object()) continue;
        const uint64_t id = j.value("id", uint64_t{0});
        if (!r->holding.count(id) || !I.tasks.count(id)) continue;  // stale
        EvalResult res;
        try {
          res = eval_result_from_json(j.at("result"));
        } catch (const nlohmann::json::exception& e) {
          throw std::runtime_error(I.name(*r) + " sent a malformed result: " + e.what());
        }
        r->holding.erase(id);
        I.tasks.erase(id);
        done->emplace_back(id, std::move(res));
      }
    }
    // who is lost
    for (auto& r : I.ranks) {
      if (!r.live) continue;
      std::string why;
      if (r.pid && r.host == I.my_host && local_process_gone(r.pid)) why = "has died";
      else if (!r.holding.empty() && since(r.last_heard) > I.timeout_s) {
        char b[96];
        std::snprintf(b, sizeof b, "sent nothing for %.0f s while evaluating", I.timeout_s);
        why = b;
      } else if (!r.greeted && since(I.started) > I.timeout_s) {
        char b[96];
        std::snprintf(b, sizeof b, "sent no hello in the %.0f s since the search started", I.timeout_s);
        why = b;
      }
      if (why.empty()) {
        if (since(r.last_ping) > 1.0) {  // rank 0 is alive: idle ranks wait for it
          I.out.send(r.rank, kPing, "");
          r.last_ping = Clock::now();
        }
        continue;
      }
      r.live = false;
      ++I.lost;
      std::string which;
      for (uint64_t id : r.holding) {
        const EvalTask& t = I.tasks.at(id);
        which += (which.empty() ? "" : ", ") + t.key;
        I.queue.push_front(id);
      }
      std::fprintf(stderr, "\noptimize: %s %s; %s\n", I.name(r).c_str(), why.c_str(),
                   which.empty() ? "it held no evaluation"
                                 : ("its evaluation of " + which + " goes to another rank").c_str());
      r.holding.clear();
    }
    bool any_live = false;
    for (const auto& r : I.ranks) any_live |= r.live;
    if (!any_live)
      throw std::runtime_error("every worker rank is lost; the search stops after its last complete generation "
                               "(continue it with --resume)");
    I.out.tidy();
    if (done->size() > done_before || I.tasks.empty() || Clock::now() >= until) return true;
    if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

int mpi_worker_main(const EvalContext& ctx, int rank, int workers, double rank_timeout_s, bool* finalize) {
  *finalize = true;
  Outbox out;
  out.send(0, kHello, nlohmann::json{{"host", host_name()}, {"pid", getpid()}, {"workers", workers}}.dump());
  std::list<std::pair<nlohmann::json, std::unique_ptr<Evaluation>>> running;
  auto last_from_0 = Clock::now(), last_beat = Clock::now();
  for (;;) {
    bool busy = false;
    for (auto it = running.begin(); it != running.end();) {
      if (it->second->poll()) {
        const nlohmann::json j = {{"id", it->first["id"]}, {"result", eval_result_to_json(it->second->result())}};
        out.send(0, kResult, j.dump());
        it = running.erase(it);
        busy = true;
      } else {
        ++it;
      }
    }
    int from = 0, tag = 0;
    std::string text;
    while (receive(0, &from, &tag, &text)) {
      busy = true;
      last_from_0 = Clock::now();
      if (tag == kStop) {
        for (auto& r : running) r.second->terminate();
        *finalize = text == "finalize";
        out.tidy();
        return 0;
      }
      if (tag != kTask) continue;
      const nlohmann::json j = nlohmann::json::parse(text);
      EvalTask t;
      t.index = j.at("index").get<size_t>();
      t.phenotype.chain = j.at("chain").get<std::string>();
      t.phenotype.values = j.at("values").get<std::vector<int64_t>>();
      t.key = j.at("key").get<std::string>();
      t.seed = j.at("seed").get<uint64_t>();
      t.trials = j.at("trials").get<int>();
      t.first_trial = j.at("first_trial").get<int>();
      t.solver = j.at("solver").get<std::string>();
      t.target = j.at("target").get<std::string>();
      running.emplace_back(j, std::make_unique<Evaluation>(ctx, t));
    }
    if (!running.empty() && since(last_beat) > 1.0) {
      out.send(0, kBeat, "");
      last_beat = Clock::now();
    }
    if (interrupt_signal()) {
      for (auto& r : running) r.second->terminate();
      *finalize = false;
      return 130;
    }
    if (since(last_from_0) > rank_timeout_s) {
      std::fprintf(stderr, "optimize: rank %d: rank 0 sent nothing for %.0f s; ending\n", rank, rank_timeout_s);
      for (auto& r : running) r.second->terminate();
      *finalize = false;
      return 3;
    }
    out.tidy();
    if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace chainsim
