// The tick loop of a run. See lockstep_server.h and docs/architecture.md
// ("A tick"). Each tick: who runs (the barrier), their TickBegins (sensors at
// now), the physics steps through the tick while they compute, their
// TickEnds collected and applied in endpoint-index order.
#include "cosim/lockstep_server.h"

#include <signal.h>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it
#include <boost/asio.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include "cosim/barrier.h"
#include "cosim/early_stop.h"
#include "cosim/endpoints.h"
#include "text/number_text.h"
#include "output/run_events.h"
#include "output/run_output.h"
#include "output/run_summary.h"
#include "output/scene_json.h"
#include "output/touch_edges.h"
#include "output/trace_writer.h"
#include "environment/pipe_path.h"
#include "physics/divergence.h"
#include "physics/world.h"

namespace chainsim {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;
// how often the run loop looks for signals (SIGINT, SIGTERM), wall clock
constexpr std::chrono::milliseconds kSignalPollInterval{20};

void say(const RunOptions& options, const std::string& message) {
  if (!options.quiet) std::fprintf(stderr, "chainsim: %s\n", message.c_str());
}

namespace {

// what chainsim-pic left at the end of its run (pic_module.h), or why not
nlohmann::json read_pic_stats(const std::string& path) {
  std::ifstream in(path);
  if (!in) return {{"error", "chainsim-pic left no figures (" + path + "): it ended before the run did"}};
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    return {{"error", std::string("chainsim-pic's figures are not JSON: ") + e.what()}};
  }
}

// the sensor part of a module's TickBegin
void fill_sensors(const ModuleSample& s, cs_tick_begin* tb) {
  tb->n_servos = static_cast<uint8_t>(s.n_servos);
  for (int k = 0; k < s.n_servos; ++k) tb->servo_pos[k] = s.servo_position_wire[k];
  tb->n_adc = static_cast<uint8_t>(s.n_adc);
  for (int k = 0; k < s.n_adc; ++k) tb->adc[k] = std::min<uint16_t>(s.adc[k], CS_ADC_COUNTS_MAX);
  tb->digital_in = s.digital_in;
  tb->n_counters = static_cast<uint8_t>(s.n_counters);
  for (int k = 0; k < s.n_counters; ++k) tb->counter[k] = s.counter[k];
}

class Server : public BarrierSink {
 public:
  Server(const Scene& scene, const RunOptions& opt, std::vector<ServoCommand>* record)
      : scene_(scene),
        opt_(opt),
        record_(record),
        chain_(compile_chain(scene)),
        world_(scene.world, chain_),
        n_modules_(world_.module_count()),
        signals_(io_, SIGINT, SIGTERM),
        columns_(sensor_columns(chain_)),
        trace_(world_, TraceWriter::interval_for(world_, scene.trace_hz), columns_),
        touch_(n_modules_, columns_),
        discovery_us_(std::llround(scene.discovery_s * 1e6)),
        energy_j_(n_modules_, 0.0),
        early_(scene.stop_when, scene.world.environment.type == EnvironmentType::Pipe
                                    ? std::make_shared<PipeProgress>(layout_pipe(scene.world.environment.pipe))
                                    : nullptr) {
    std::vector<int> servos;
    for (int m = 0; m < n_modules_; ++m) servos.push_back(world_.servo_count(m));
    barrier_ = std::make_unique<Barrier>(servos, scene.tick_us);
    out_ = std::make_unique<RunOutput>(opt.out_dir, endpoint_types(scene));
    endpoints_ = std::make_unique<Endpoints>(scene, opt, out_.get(), &io_);
  }

  RunResult run();

  // BarrierSink: outputs applied after the step of this tick, in force from the next one
  void servo(int module, int servo, bool enabled, int32_t setpoint_wire) override {
    if (module >= n_modules_) return;
    world_.set_servo_enabled(module, servo, enabled);
    if (enabled) world_.set_servo_setpoint_wire(module, servo, setpoint_wire);
    if (record_)
      record_->push_back({now_us_ + scene_.tick_us, static_cast<int16_t>(module), static_cast<int8_t>(servo),
                          static_cast<int8_t>(enabled), setpoint_wire});
  }
  void bus_event(int64_t t_us, const char* line) override {
    out_->bus(t_us, line);
    if (opt_.observer) opt_.observer->bus_line(t_us, line);
  }
  void module_log(int endpoint, int64_t t_us, const char* line) override {
    out_->module_log(endpoint, t_us, line);
    if (opt_.observer) opt_.observer->module_log(endpoint, t_us, line);
  }
  void address(int endpoint, int64_t t_us, uint8_t address) override {
    out_->event(address_event(t_us, endpoint, (*endpoints_)[endpoint].type, address));
  }
  void queue_full(int endpoint, int64_t t_us, int queued_bytes) override {
    if (queue_full_said_.size() <= static_cast<size_t>(endpoint)) queue_full_said_.resize(endpoint + 1, false);
    if (queue_full_said_[endpoint]) return;  // the first of each endpoint; bus.log has every one
    queue_full_said_[endpoint] = true;
    const Endpoint& e = (*endpoints_)[endpoint];
    out_->event(queue_full_event(t_us, endpoint, e.type, queued_bytes));
    if (!opt_.quiet)
      std::fprintf(stderr, "chainsim: warning: %s %d (%s) sends I2C frames faster than the bus carries them: a frame "
                           "dropped at t=%s s with %d bytes of its own waiting (bus.log has every drop)\n",
                   endpoint < n_modules_ ? "module" : "endpoint", endpoint, e.type.c_str(),
                   fixed_text(t_us * 1e-6, 6).c_str(), queued_bytes);
  }

 private:
  // one tick's exchange, in two halves with the physics step between them:
  // send_begin sends each awake endpoint its TickBegin (sensors at now),
  // collect_end reads their TickEnds and stores them in the barrier
  void send_begin(const std::vector<int>& awake);
  bool collect_end(const std::vector<int>& awake);
  // the physics through one tick: the steps, the energy, the trace rows
  void step_tick();
  void write_trace_row_if_due();
  // after a SIGCHLD: a fault for each endpoint whose process has ended
  // (asleep ones too, which no exchange would notice); false if the run stops
  bool check_ended();
  // after a tick: a divergence of the physics stops the run (or is said once,
  // --on-divergence=warn); false if the run stops
  bool check_divergence();
  // a write of the run's files failed (disk full): the run stops at once,
  // naming the file; false if so
  bool check_output();
  // at discovery_us_: a module without an I2C address that may not stay
  // silent is a fault (exit kExitSilentModule); false if the run stops
  bool judge_discovery();
  // a fault of e: returns true if the run goes on (limp mode); else the run
  // stops with exit code `code`
  bool fault(Endpoint& e, const std::string& what, int code = kExitModuleFault);
  RunSummary summary(double wall_s, const Eigen::Vector3d& displacement_m);

  const Scene& scene_;
  const RunOptions& opt_;
  std::vector<ServoCommand>* record_;
  const ChainModel chain_;  // the scene's chain, compiled once: the world, trace and scene.json read it
  World world_;
  const int n_modules_;
  asio::io_context io_;
  asio::signal_set signals_;
  int interrupted_ = 0;
  std::unique_ptr<Barrier> barrier_;
  std::unique_ptr<RunOutput> out_;
  std::unique_ptr<Endpoints> endpoints_;
  std::vector<SensorColumn> columns_;  // the sensors of the chain, as the trace has them
  TraceWriter trace_;
  std::string row_;
  TouchEdges touch_;
  const int64_t discovery_us_;
  bool discovery_judged_ = false;
  std::vector<int> silent_, allowed_silent_;
  std::vector<double> energy_j_;
  EarlyStop early_;          // the scene's stop_when
  std::string early_why_;    // set when one fired: the run ends after this tick
  std::vector<bool> queue_full_said_;  // per endpoint: its first dropped frame was reported
  int64_t now_us_ = 0;
  std::string stop_message_;
  int stop_code_ = kExitOk;
  uint64_t exchanges_ = 0;
  unsigned child_ends_seen_ = 0;
  bool divergence_said_ = false;
};

bool Server::check_output() {
  if (out_->write_error().empty()) return true;
  stop_message_ = out_->write_error() + " at t=" + fixed_text(now_us_ * 1e-6, 6) + " s";
  stop_code_ = kExitOutput;
  return false;
}

bool Server::check_divergence() {
  const auto d = find_divergence(world_);
  if (!d) return true;
  const std::string what = "physics diverged: " + d->what + " at t=" + fixed_text(now_us_ * 1e-6, 6) + " s";
  if (opt_.on_divergence == DivergenceMode::Warn && !d->non_finite) {
    if (!divergence_said_) {
      bus_event(now_us_, ("warning " + what).c_str());
      out_->event(warning_event(now_us_, what));
      std::fprintf(stderr, "chainsim: warning: %s; the run goes on (--on-divergence=warn)\n", what.c_str());
      divergence_said_ = true;
    }
    return true;
  }
  bus_event(now_us_, ("fault " + what).c_str());
  out_->event(fault_event(now_us_, -1, "", what));
  out_->flush();
  stop_message_ = what;
  stop_code_ = kExitDivergence;
  return false;
}

bool Server::check_ended() {
  const unsigned n = child_end_count();
  if (n == child_ends_seen_) return true;
  child_ends_seen_ = n;
  for (int i = 0; i < endpoints_->size(); ++i) {
    Endpoint& e = (*endpoints_)[i];
    if (e.attached || !e.fault.empty() || !e.proc.running()) continue;
    if (const auto& st = e.proc.poll())
      if (!fault(e, "ended between exchanges: " + st->text())) return false;
  }
  return true;
}

bool Server::judge_discovery() {
  discovery_judged_ = true;
  std::vector<int> answered;
  for (int i = 0; i < n_modules_; ++i) {
    if (barrier_->address(i) != 0) answered.push_back(i);
    else if (scene_.modules[i].may_stay_silent) allowed_silent_.push_back(i);
    else silent_.push_back(i);
  }
  out_->event(discovery_event(now_us_, answered, allowed_silent_, silent_));
  for (size_t k = 0; k < silent_.size(); ++k) {
    Endpoint& e = (*endpoints_)[silent_[k]];
    if (!e.fault.empty()) continue;  // it crashed or hung: that fault says more
    std::string what = "did not answer discovery: it has no I2C address (judged at central.discovery_s)";
    const size_t others = silent_.size() - 1;  // behind the first, the shipped central control stops
    if (k == 0 && others > 0)
      what += "; " + std::string(others == 1 ? "module " : "modules ") + std::to_string(silent_[1]) +
              (others == 2 ? " and " : others > 2 ? " to " : "") +
              (others >= 2 ? std::to_string(silent_.back()) : "") + " after it " + (others == 1 ? "has" : "have") +
              " none either";
    what += "; a module that takes no part in discovery says may_stay_silent: true in the scene";
    if (!fault(e, what, kExitSilentModule)) return false;
  }
  return true;
}

bool Server::fault(Endpoint& e, const std::string& what, int code) {
  e.fault = endpoints_->describe_end(e, what, now_us_);
  bus_event(now_us_, ("fault " + e.fault).c_str());
  out_->event(fault_event(now_us_, e.index, e.type, e.fault));
  out_->flush();
  endpoints_->cut_off(e);
  if (opt_.on_fault == FaultMode::Limp) {
    say(opt_, "fault: " + e.fault + "; it is powered off and the run goes on (limp mode)");
    barrier_->power_off(e.index);
    if (e.index < n_modules_) world_.set_module_powered(e.index, false);
    return true;
  }
  stop_message_ = e.fault;
  stop_code_ = code;
  return false;
}

void Server::send_begin(const std::vector<int>& awake) {
  cs_msg msg{};
  msg.type = CS_MSG_TICK_BEGIN;
  for (int i : awake) {
    Endpoint& e = (*endpoints_)[i];
    cs_tick_begin& tb = msg.u.tick_begin;
    tb = cs_tick_begin{};
    if (i < n_modules_) {
      ModuleSample s;
      world_.sample(i, &s);
      fill_sensors(s, &tb);
    }
    barrier_->fill_begin(i, now_us_, &tb);
    e.replied = false;
    e.reply_error.clear();
    const std::string err = e.link->send(msg);
    if (!err.empty()) {
      e.replied = true;
      e.reply_error = err;
      continue;
    }
    ++exchanges_;
  }
}

bool Server::collect_end(const std::vector<int>& awake) {
  // collect every reply, in index order (the order they are applied in anyway);
  // attached modules (maybe in a debugger) have no deadline
  const auto deadline = Clock::now() + std::chrono::duration<double>(opt_.module_timeout_s);
  for (int i : awake) {
    Endpoint& e = (*endpoints_)[i];
    if (e.replied) continue;
    for (;;) {
      const auto got = e.link->receive(100);
      if (got == ModuleLink::Receive::Pending) {
        io_.poll();  // signals
        if (interrupted_) return false;
        if (!e.attached && Clock::now() > deadline) break;
        continue;
      }
      e.replied = true;
      if (got == ModuleLink::Receive::Failed)
        e.reply_error = e.link->error();
      else if (e.link->received().type != CS_MSG_TICK_END)
        e.reply_error = std::string("sent ") + cs_msg_name(e.link->received().type) + " instead of TICK_END";
      else
        e.reply_error = barrier_->store_end(e.index, now_us_, e.link->received().u.tick_end);
      break;
    }
  }
  if (interrupted_) return false;
  for (int i : awake) {
    Endpoint& e = (*endpoints_)[i];
    std::string what = e.reply_error;
    if (!e.replied)
      what = "did not answer within " + fixed_text(opt_.module_timeout_s, 1) +
             " s (wall clock): " + endpoints_->silence_cause(e);
    if (what.empty()) continue;
    if (!fault(e, what)) return false;
  }
  return true;
}

void Server::write_trace_row_if_due() {
  if (!trace_.row_due(&row_)) return;
  out_->trace(row_);
  if (opt_.observer) opt_.observer->trace_row(row_);
  if (!early_.empty() && early_why_.empty() && n_modules_ > 0) {
    const int last = n_modules_ - 1;
    if (early_.check(world_.time_us(), world_.body_state(0, 0).position,
                     world_.body_state(last, world_.body_count(last) - 1).position)) {
      early_why_ = early_.why();
      if (!opt_.quiet) std::fprintf(stderr, "%schainsim: %s\n", opt_.progress_terminal ? "\n" : "", early_why_.c_str());
    }
  }
}

void Server::step_tick() {
  const int substeps = static_cast<int>(scene_.tick_us / world_.dt_us());
  const double vs = scene_.world.servo.supply_v;
  const double dt_s = world_.dt_us() * 1e-6;
  for (int k = 0; k < substeps; ++k) {
    world_.step();
    for (int m = 0; m < n_modules_; ++m) energy_j_[m] += world_.module_supply_current_a(m) * vs * dt_s;
    write_trace_row_if_due();
  }
}

RunResult Server::run() {
  const auto wall0 = Clock::now();
  signals_.async_wait([this](const boost::system::error_code& ec, int sig) {
    if (!ec) interrupted_ = sig;
  });
  const Eigen::Vector3d com0 = world_.chain_com();
  const int64_t end_us = std::llround(scene_.duration_s * 1e6);
  row_.reserve(1 << 14);
  out_->trace(trace_.header());
  const nlohmann::json scene_desc = write_scene_json(out_.get(), scene_, chain_);
  if (opt_.observer) opt_.observer->started(scene_desc, trace_.header());

  bool ok = true;
  try {
    endpoints_->start();
    ok = endpoints_->handshake([this](Endpoint& e, const std::string& what) { return fault(e, what); },
                               &interrupted_);
  } catch (const std::exception& ex) {
    stop_message_ = ex.what();
    stop_code_ = kExitBadInput;
    ok = false;
  }
  std::vector<int> awake;
  awake.reserve(endpoints_->size());
  write_trace_row_if_due();
  auto last_progress = Clock::now();
  auto last_flush = last_progress;
  auto last_signal_poll = last_progress;
  while (ok && now_us_ < end_us) {
    // The modules compute this tick while the physics steps through it: they
    // get the sensors at now, and their outputs (set-points) are in force
    // from the next tick, one HAL tick of actuation latency, as on the board
    // where a set-point waits for the next servo pulse anyway. The bus and
    // the sync lines see the outputs at now, as before.
    barrier_->due(now_us_, &awake, this);
    if (!awake.empty()) send_begin(awake);
    step_tick();
    if (!awake.empty() && !collect_end(awake)) {
      now_us_ += scene_.tick_us;  // the physics did step: the trace reaches here
      ok = false;
      break;
    }
    barrier_->apply(now_us_, this);
    now_us_ += scene_.tick_us;
    if (!check_divergence() || !check_output()) {
      ok = false;
      break;
    }
    if (!check_ended()) {
      ok = false;
      break;
    }
    if (!discovery_judged_ && now_us_ >= discovery_us_ && !judge_discovery()) {
      ok = false;
      break;
    }
    touch_.sample(
        world_, [this](const char* line) { bus_event(now_us_, line); },
        [this](int m, const std::string& sensor, bool contact) {
          out_->event(touch_event(now_us_, m, sensor, contact));
        });
    // signals arrive through the io_context; polling it costs a system call
    // (epoll_wait), so it is polled every kSignalPollInterval of wall time
    // rather than every tick (the clock is read without one)
    const auto now = Clock::now();
    if (now - last_signal_poll >= kSignalPollInterval) {
      last_signal_poll = now;
      io_.poll();
    }
    if (interrupted_) {
      ok = false;
      break;
    }
    if (!early_why_.empty()) break;  // stop_when: the run ends here, finished
    if (now - last_flush > std::chrono::seconds(1)) {
      out_->flush();
      last_flush = now;
    }
    if (opt_.progress && now - last_progress > std::chrono::duration<double>(opt_.progress_every_s)) {
      last_progress = now;
      const double wall = std::chrono::duration<double>(now - wall0).count();
      std::fprintf(stderr, "%schainsim: t=%s/%s s, %sx real time%s", opt_.progress_terminal ? "\r" : "",
                   fixed_text(now_us_ * 1e-6, 2).c_str(), fixed_text(end_us * 1e-6, 2).c_str(),
                   fixed_text(now_us_ * 1e-6 / wall, 2).c_str(), opt_.progress_terminal ? " " : "\n");
    }
  }
  if (opt_.progress && opt_.progress_terminal) std::fprintf(stderr, "\n");
  if (interrupted_) {
    stop_code_ = kExitInterrupted;
    stop_message_ = std::string("interrupted by ") + strsignal(interrupted_) + " at t=" +
                    fixed_text(now_us_ * 1e-6, 6) + " s";
  }
  endpoints_->shutdown(stop_message_.empty());
  out_->flush();
  if (stop_code_ == kExitOk) check_output();  // the last flush

  RunResult r;
  r.wall_time_s = std::chrono::duration<double>(Clock::now() - wall0).count();
  r.exit_code = stop_code_;
  r.message = stop_message_;
  r.exchanges = exchanges_;
  r.summary = summary_json(scene_, summary(r.wall_time_s, world_.chain_com() - com0));
  try {
    out_->write_summary(r.summary);
  } catch (const std::exception& e) {
    // the files written so far stay; no summary.json.tmp is left behind
    if (r.exit_code == kExitOk || r.exit_code == kExitOutput) {
      r.exit_code = kExitOutput;
      r.message = r.message.empty() ? e.what() : r.message + "; " + e.what();
    }
  }
  if (opt_.observer) opt_.observer->finished(r.summary);
  return r;
}

RunSummary Server::summary(double wall_s, const Eigen::Vector3d& displacement_m) {
  RunSummary s;
  s.sim_time_us = now_us_;
  s.wall_time_s = wall_s;
  s.limp_mode = opt_.on_fault == FaultMode::Limp;
  s.trace_sha256 = out_->trace_sha256();
  s.exchanges = exchanges_;
  s.degenerate_lcp_steps = world_.degenerate_lcp_steps();
  for (int i = 0; i < endpoints_->size(); ++i) {
    const Endpoint& e = (*endpoints_)[i];
    EndpointSummary es;
    es.index = e.index;
    es.type = e.type;
    es.program = e.program;
    es.target = target_name(e.target);
    if (e.target == Target::Pic) es.pic = read_pic_stats(e.pic_stats);
    es.pid = e.pid ? e.pid : static_cast<uint32_t>(std::max(0, e.proc.pid()));
    es.fault = e.fault;
    es.exchanges = barrier_->exchanges(e.index);
    es.i2c_address = barrier_->address(e.index);
    es.addressed_us = barrier_->addressed_us(e.index);
    if (e.index < n_modules_) es.energy_j = energy_j_[e.index];
    s.endpoints.push_back(es);
  }
  s.displacement_m = displacement_m;
  s.discovery_us = discovery_us_;
  s.discovery_judged = discovery_judged_;
  s.silent = silent_;
  s.allowed_silent = allowed_silent_;
  s.exit_code = stop_code_;
  s.stopped_by = stop_message_;
  s.early_stop = early_why_;
  return s;
}

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options, std::vector<ServoCommand>* record) {
  signal(SIGPIPE, SIG_IGN);
  signal(SIGXFSZ, SIG_IGN);  // a file-size limit is a failed write to report, not a kill
  Server server(scene, options, record);
  return server.run();
}

}  // namespace chainsim
