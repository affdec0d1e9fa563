#include "cosim/lockstep_server.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it
#include <boost/asio.hpp>

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "cosim/barrier.h"
#include "cosim/child_process.h"
#include "cosim/module_link.h"
#include "output/run_output.h"
#include "output/scene_json.h"
#include "physics/world.h"

namespace chainsim {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kTerminateGraceMs = 1000;

// writes trace rows every interval of simulated time, the same way for a
// co-simulation and for a replay, so both give the same bytes
class TraceClock {
 public:
  TraceClock(const Scene& s)
      : interval_us_(std::max<int64_t>(s.world.dt_us, std::llround(1e6 / s.trace_hz))) {}
  template <class Write>
  void maybe_write(const World& w, std::string* row, Write write) {
    if (w.time_us() < next_us_) return;
    next_us_ += interval_us_;
    row->clear();
    w.append_trace_row(row);
    write(*row);
  }

 private:
  int64_t interval_us_;
  int64_t next_us_ = 0;
};

std::string last_line_of(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::string fmt_time(int64_t t_us) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6f s", t_us * 1e-6);
  return b;
}

std::string make_socket_dir() {
  std::string tmpl = (std::filesystem::temp_directory_path() / "chainsim-XXXXXX").string();
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a private socket directory in /tmp");
  chmod(tmpl.c_str(), 0700);
  return tmpl;
}

class Server : public BarrierSink {
 public:
  Server(const Scene& scene, const RunOptions& opt, std::vector<ServoCommand>* record)
      : scene_(scene), opt_(opt), record_(record), world_(scene.world), signals_(io_, SIGINT, SIGTERM) {
    n_modules_ = world_.module_count();
    std::vector<int> servos;
    for (int m = 0; m < n_modules_; ++m) servos.push_back(world_.servo_count(m));
    barrier_ = std::make_unique<Barrier>(servos, scene.tick_us);
    for (int m = 0; m <= n_modules_; ++m) {
      const SceneModule& sm = m < n_modules_ ? scene.modules[m] : scene.central;
      auto e = std::make_unique<Endpoint>();
      e->index = m;
      e->type = m < n_modules_ ? sm.type : "central";
      e->program = sm.firmware;
      e->params = sm.params;
      ep_.push_back(std::move(e));
    }
    std::vector<std::string> names;
    for (auto& e : ep_) names.push_back(e->type);
    out_ = std::make_unique<RunOutput>(opt.out_dir, names);
    energy_j_.assign(n_modules_, 0.0);
    touch_.assign(n_modules_, 0);
  }

  RunResult run();

  // BarrierSink
  void servo(int module, int servo, bool enabled, double rad) override {
    if (module >= n_modules_) return;
    // the barrier reads the wire value as millidegrees; a linear servo's is
    // micrometres and a screw drive's per mille (world.h): back to the wire
    // value (exact) and into the actuator's own unit
    const World::ServoKind kind = world_.servo_kind(module, servo);
    const double v = kind == World::ServoKind::Rotary
                         ? rad
                         : World::servo_from_wire(kind, static_cast<int32_t>(std::lround(rad * 180.0 / M_PI * 1000.0)));
    world_.set_servo_enabled(module, servo, enabled);
    if (enabled) world_.set_servo_setpoint(module, servo, v);
    // applied after the step of this tick: in force from the next one
    if (record_) record_->push_back({now_us_ + scene_.tick_us, static_cast<int16_t>(module), static_cast<int8_t>(servo),
                                     static_cast<int8_t>(enabled), v});
  }
  void bus_event(int64_t t_us, const char* line) override {
    out_->bus(t_us, line);
    if (opt_.observer) opt_.observer->bus_line(t_us, line);
  }
  void module_log(int endpoint, int64_t t_us, const char* line) override { out_->module_log(endpoint, t_us, line); }

 private:
  struct Endpoint {
    int index;
    std::string type;
    std::string program;
    std::map<std::string, int32_t> params;
    ChildProcess proc;
    bool attached = false;
    std::shared_ptr<ModuleLink> link;
    uint32_t pid = 0;
    std::string fault;        // empty while healthy
    bool replied = false;     // this tick
    std::string reply_error;
  };

  std::string name_of(const Endpoint& e) const {
    const uint32_t pid = e.pid ? e.pid : (e.proc.pid() > 0 ? static_cast<uint32_t>(e.proc.pid()) : 0);
    std::string s = (e.index == n_modules_ ? "central control" : "module " + std::to_string(e.index)) +
                    " (" + e.type;
    if (pid) s += ", pid " + std::to_string(pid);
    return s + ")";
  }

  // a name is looked up in firmware_dir (DIR[:DIR...]) first, then next to chainsim
  std::string program_path(const std::string& program) const {
    if (program.find('/') != std::string::npos) return program;
    const std::string& dirs = opt_.firmware_dir;
    for (size_t b = 0; b < dirs.size();) {
      const size_t e = std::min(dirs.find(':', b), dirs.size());
      const std::string p = dirs.substr(b, e - b) + "/" + program;
      if (e > b && access(p.c_str(), X_OK) == 0) return p;
      b = e + 1;
    }
    return executable_dir() + "/" + program;
  }

  void start_processes();
  bool handshake();
  void on_hello(std::shared_ptr<ModuleLink> link);
  // one tick's exchange, in two halves with the physics step between them:
  // send_begin sends each awake endpoint its TickBegin (sensors at now),
  // collect_end reads their TickEnds and stores them in the barrier
  bool send_begin(const std::vector<int>& awake);
  bool collect_end(const std::vector<int>& awake);
  // a fault of e: returns true if the run goes on (limp mode)
  bool fault(Endpoint& e, const std::string& what);
  std::string describe_end(Endpoint& e, const std::string& what);
  void shutdown_all();
  // bus-log lines for changes of each module's touch input (digital input 0)
  void log_touch_edges() {
    for (int m = 0; m < n_modules_; ++m) {
      ModuleSample s;
      world_.sample(m, &s);
      const uint8_t level = s.digital_in & 1u;
      if (level == touch_[m]) continue;
      touch_[m] = level;
      char line[64];
      std::snprintf(line, sizeof line, "touch endpoint=%d level=%u", m, level);
      bus_event(now_us_, line);
    }
  }
  nlohmann::json summary(const RunResult& r, double wall_s);
  void say(const std::string& s) const {
    if (!opt_.quiet) std::fprintf(stderr, "chainsim: %s\n", s.c_str());
  }

  const Scene& scene_;
  const RunOptions& opt_;
  std::vector<ServoCommand>* record_;
  World world_;
  asio::io_context io_;
  asio::signal_set signals_;
  int interrupted_ = 0;
  std::unique_ptr<asio::local::stream_protocol::acceptor> acceptor_;
  std::string socket_dir_, socket_path_;
  int n_modules_ = 0;
  std::vector<std::unique_ptr<Endpoint>> ep_;
  std::unique_ptr<Barrier> barrier_;
  std::unique_ptr<RunOutput> out_;
  std::vector<double> energy_j_;
  std::vector<uint8_t> touch_;  // last logged touch level per module
  int64_t now_us_ = 0;
  std::string stop_message_;
  int stop_code_ = kExitOk;
  uint64_t exchanges_ = 0;
};

void Server::start_processes() {
  socket_dir_ = make_socket_dir();
  socket_path_ = socket_dir_ + "/chainsim.sock";
  acceptor_ = std::make_unique<asio::local::stream_protocol::acceptor>(
      io_, asio::local::stream_protocol::endpoint(socket_path_));
  chmod(socket_path_.c_str(), 0600);
  for (auto& ep : ep_) {
    Endpoint& e = *ep;
    const std::string prog = program_path(e.program);
    e.attached = opt_.attach.count(e.index) > 0;
    if (e.attached) {
      say("waiting for " + name_of(e) + " started by hand:\n  CHAINSIM_SOCKET=" + socket_path_ +
          " CHAINSIM_MODULE_INDEX=" + std::to_string(e.index) + " CHAINSIM_MODULE_TYPE=" + e.type +
          " gdb " + prog);
      continue;
    }
    if (access(prog.c_str(), X_OK) != 0)
      throw std::runtime_error("program for " + name_of(e) + " not found or not executable: " + prog);
    ChildSpec spec;
    spec.program = prog;
    spec.env = {"CHAINSIM_SOCKET=" + socket_path_, "CHAINSIM_MODULE_INDEX=" + std::to_string(e.index),
                "CHAINSIM_MODULE_TYPE=" + e.type};
    spec.stdout_path = out_->module_file(e.index, "out");
    e.proc.spawn(spec);
  }
}

void Server::on_hello(std::shared_ptr<ModuleLink> link) {
  link->async_receive([this, link](const std::string& err) {
    // a peer that breaks the handshake is dropped; the module it should have
    // been is then reported when it does not connect in time
    if (!err.empty() || link->received().type != CS_MSG_HELLO) {
      say("dropped a connection: " +
          (err.empty() ? std::string("it sent ") + cs_msg_name(link->received().type) + " instead of HELLO" : err));
      link->close();
      return;
    }
    const cs_hello& h = link->received().u.hello;
    cs_msg reply{};
    std::string why;
    if (h.module_index >= ep_.size())
      why = "module index " + std::to_string(h.module_index) + " is not in this scene (" +
            std::to_string(ep_.size()) + " endpoints)";
    else if (ep_[h.module_index]->link)
      why = "module index " + std::to_string(h.module_index) + " is already connected";
    else if (ep_[h.module_index]->type != h.type)
      why = "module " + std::to_string(h.module_index) + " is a " + ep_[h.module_index]->type + ", not a " + h.type;
    else if (!ep_[h.module_index]->attached && ep_[h.module_index]->proc.pid() != static_cast<pid_t>(h.pid))
      why = "module " + std::to_string(h.module_index) + " was not started by this server (pid " +
            std::to_string(h.pid) + ")";
    if (!why.empty()) {
      reply.type = CS_MSG_REJECT;
      std::snprintf(reply.u.reject.reason, CS_REASON_MAX, "%s", why.c_str());
      link->send(reply);
      link->close();
      say("rejected a connection: " + why);
      return;
    }
    Endpoint& e = *ep_[h.module_index];
    e.pid = h.pid;
    reply.type = CS_MSG_WELCOME;
    cs_welcome& w = reply.u.welcome;
    w.version = CS_VERSION;
    w.module_index = h.module_index;
    w.tick_us = static_cast<uint32_t>(scene_.tick_us);
    w.seed = scene_.seed;
    for (const auto& [k, v] : e.params) {
      if (w.n_params >= CS_PARAMS_MAX) break;
      std::snprintf(w.params[w.n_params].name, CS_PARAM_NAME_MAX, "%s", k.c_str());
      w.params[w.n_params].value = v;
      ++w.n_params;
    }
    const std::string err2 = link->send(reply);
    if (!err2.empty()) return;
    e.link = link;
  });
}

bool Server::handshake() {
  // accept until every endpoint has said HELLO; children that die first are faults
  std::function<void()> accept_next = [&]() {
    acceptor_->async_accept([&](const boost::system::error_code& ec, asio::local::stream_protocol::socket s) {
      if (ec) return;
      on_hello(std::make_shared<ModuleLink>(std::move(s)));
      accept_next();
    });
  };
  accept_next();
  const auto deadline = Clock::now() + std::chrono::duration<double>(opt_.module_timeout_s);
  for (;;) {
    bool all = true;
    for (auto& e : ep_) all &= static_cast<bool>(e->link) || !e->fault.empty();
    if (all) break;
    if (interrupted_) return false;
    for (auto& ep : ep_) {
      Endpoint& e = *ep;
      if (e.link || !e.fault.empty() || e.attached) continue;
      if (e.proc.poll()) {
        if (!fault(e, "ended before connecting: " + e.proc.poll()->text())) return false;
      } else if (Clock::now() > deadline) {
        char b[64];
        std::snprintf(b, sizeof b, "%.1f", opt_.module_timeout_s);
        if (!fault(e, std::string("did not connect within ") + b + " s")) return false;
      }
    }
    io_.run_one_for(std::chrono::milliseconds(20));
  }
  acceptor_->close();
  io_.poll();
  return true;
}

std::string Server::describe_end(Endpoint& e, const std::string& what) {
  std::string s = name_of(e) + " " + what;
  if (!e.attached && e.proc.pid() > 0) {
    // a process that closed its socket is on its way out: give it a moment to be reaped
    const bool dying = what.rfind("closed its socket", 0) == 0;
    if (const auto& st = e.proc.wait_for(dying ? 1000 : 0)) {
      if (dying) s = name_of(e) + " ended: " + st->text();
      else if (what.find(st->text()) == std::string::npos) s += " (then ended: " + st->text() + ")";
    }
    const std::string last = last_line_of(out_->module_file(e.index, "out"));
    if (!last.empty()) s += "; its last output: \"" + last + "\"";
  }
  return s + " at t=" + fmt_time(now_us_);
}

bool Server::fault(Endpoint& e, const std::string& what) {
  e.fault = describe_end(e, what);
  bus_event(now_us_, ("fault " + e.fault).c_str());
  out_->flush();
  if (e.link) e.link->close();
  if (!e.attached) e.proc.terminate(kTerminateGraceMs);
  if (opt_.on_fault == FaultMode::Limp) {
    say("fault: " + e.fault + "; it is powered off and the run goes on (limp mode)");
    barrier_->power_off(e.index);
    if (e.index < n_modules_) world_.set_module_powered(e.index, false);
    return true;
  }
  stop_message_ = e.fault;
  stop_code_ = kExitModuleFault;
  return false;
}

bool Server::send_begin(const std::vector<int>& awake) {
  cs_msg msg{};
  msg.type = CS_MSG_TICK_BEGIN;
  for (int i : awake) {
    Endpoint& e = *ep_[i];
    cs_tick_begin& tb = msg.u.tick_begin;
    tb = cs_tick_begin{};
    if (i < n_modules_) {
      ModuleSample s;
      world_.sample(i, &s);
      tb.n_servos = static_cast<uint8_t>(s.n_servos);
      for (int k = 0; k < s.n_servos; ++k)
        tb.servo_pos[k] = World::servo_to_wire(world_.servo_kind(i, k), s.servo_angle_rad[k]);
      tb.n_adc = static_cast<uint8_t>(s.n_adc);
      for (int k = 0; k < s.n_adc; ++k) tb.adc[k] = std::min<uint16_t>(s.adc[k], CS_ADC_COUNTS_MAX);
      tb.digital_in = s.digital_in;
      tb.n_counters = static_cast<uint8_t>(s.n_counters);
      for (int k = 0; k < s.n_counters; ++k) tb.counter[k] = s.counter[k];
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
  return true;
}

bool Server::collect_end(const std::vector<int>& awake) {
  // collect every reply, in index order (the order they are applied in anyway);
  // attached modules (maybe in a debugger) have no deadline
  const auto deadline = Clock::now() + std::chrono::duration<double>(opt_.module_timeout_s);
  for (int i : awake) {
    Endpoint& e = *ep_[i];
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
    Endpoint& e = *ep_[i];
    std::string what = e.reply_error;
    if (!e.replied) {
      char b[96];
      std::snprintf(b, sizeof b, "did not answer within %.1f s (wall clock): hung, or busy without a HAL wait",
                    opt_.module_timeout_s);
      what = b;
    }
    if (what.empty()) continue;
    if (!fault(e, what)) return false;
  }
  return true;
}

void Server::shutdown_all() {
  cs_msg bye{};
  bye.type = CS_MSG_SHUTDOWN;
  std::snprintf(bye.u.shutdown.reason, CS_REASON_MAX, "%s", stop_message_.empty() ? "run finished" : "run stopped");
  for (auto& e : ep_) {
    if (e->link && e->link->open()) {
      e->link->send(bye);
      e->link->close();
    }
  }
  std::vector<ChildProcess*> kids;
  for (auto& e : ep_) {
    if (!e->attached && e->proc.running()) e->proc.wait_for(300);
    kids.push_back(&e->proc);
  }
  terminate_all(kids, kTerminateGraceMs);
  if (acceptor_) acceptor_->close();
  std::error_code ec;
  std::filesystem::remove_all(socket_dir_, ec);
}

RunResult Server::run() {
  RunResult r;
  const auto wall0 = Clock::now();
  signals_.async_wait([this](const boost::system::error_code& ec, int sig) {
    if (!ec) interrupted_ = sig;
  });
  const Eigen::Vector3d com0 = world_.chain_com();
  const int64_t end_us = std::llround(scene_.duration_s * 1e6);
  const int substeps = static_cast<int>(scene_.tick_us / world_.dt_us());
  TraceClock trace_clock(scene_);
  std::string row;
  row.reserve(1 << 14);
  const std::string header = world_.trace_header();
  out_->trace(header);
  const nlohmann::json scene_desc = scene_json(scene_);
  {
    std::ofstream sj(out_->path("scene.json"));
    sj << scene_desc.dump(2) << "\n";
  }
  if (opt_.observer) opt_.observer->started(scene_desc, header);
  auto write_row = [&](const std::string& s) {
    out_->trace(s);
    if (opt_.observer) opt_.observer->trace_row(s);
  };

  bool ok = true;
  try {
    start_processes();
    ok = handshake();
  } catch (const std::exception& ex) {
    stop_message_ = ex.what();
    stop_code_ = kExitBadInput;
    ok = false;
  }
  std::vector<int> awake;
  awake.reserve(ep_.size());
  trace_clock.maybe_write(world_, &row, write_row);
  auto last_progress = Clock::now();
  auto last_flush = last_progress;
  const double vs = scene_.world.servo.supply_v;
  const double dt_s = world_.dt_us() * 1e-6;
  while (ok && now_us_ < end_us) {
    // The modules compute this tick while the physics steps through it: they
    // get the sensors at now, and their outputs (set-points) are in force
    // from the next tick, one HAL tick of actuation latency, as on the board
    // where a set-point waits for the next servo pulse anyway. The bus and
    // the sync lines see the outputs at now, as before.
    barrier_->due(now_us_, &awake, this);
    if (!awake.empty() && !send_begin(awake)) {
      ok = false;
      break;
    }
    for (int k = 0; k < substeps; ++k) {
      world_.step();
      for (int m = 0; m < n_modules_; ++m) energy_j_[m] += world_.module_supply_current_a(m) * vs * dt_s;
      trace_clock.maybe_write(world_, &row, write_row);
    }
    if (!awake.empty() && !collect_end(awake)) {
      now_us_ += scene_.tick_us;  // the physics did step: the trace reaches here
      ok = false;
      break;
    }
    barrier_->apply(now_us_, this);
    now_us_ += scene_.tick_us;
    log_touch_edges();
    io_.poll();
    if (interrupted_) {
      ok = false;
      break;
    }
    const auto now = Clock::now();
    if (now - last_flush > std::chrono::seconds(1)) {
      out_->flush();
      last_flush = now;
    }
    if (opt_.progress && now - last_progress > std::chrono::seconds(1)) {
      last_progress = now;
      const double wall = std::chrono::duration<double>(now - wall0).count();
      std::fprintf(stderr, "\rchainsim: t=%.2f/%.2f s, %.2fx real time ", now_us_ * 1e-6, end_us * 1e-6,
                   now_us_ * 1e-6 / wall);
    }
  }
  if (opt_.progress) std::fprintf(stderr, "\n");
  if (interrupted_) {
    stop_code_ = kExitInterrupted;
    stop_message_ = std::string("interrupted by ") + strsignal(interrupted_) + " at t=" + fmt_time(now_us_);
  }
  shutdown_all();
  out_->flush();

  const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
  r.exit_code = stop_code_;
  r.message = stop_message_;
  r.wall_time_s = wall;
  r.exchanges = exchanges_;
  const Eigen::Vector3d d = world_.chain_com() - com0;
  nlohmann::json mods = nlohmann::json::array();
  for (auto& ep : ep_) {
    const Endpoint& e = *ep;
    nlohmann::json m = {{"index", e.index},
                        {"type", e.type},
                        {"program", e.program},
                        {"pid", e.pid ? e.pid : static_cast<uint32_t>(std::max(0, e.proc.pid()))},
                        {"fault", e.fault.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.fault)},
                        {"exchanges", barrier_->exchanges(e.index)}};
    if (e.index < n_modules_) m["energy_j"] = energy_j_[e.index];
    mods.push_back(m);
  }
  const double sim_s = now_us_ * 1e-6;
  r.summary = {{"scene", scene_.name},
               {"scene_source", scene_.source},
               {"seed", scene_.seed},
               {"sim_time_s", sim_s},
               {"wall_time_s", wall},
               {"real_time_factor", wall > 0 ? sim_s / wall : 0.0},
               {"dt_us", world_.dt_us()},
               {"tick_us", scene_.tick_us},
               {"on_module_fault", opt_.on_fault == FaultMode::Limp ? "limp" : "stop"},
               {"trace_file", "trace.csv"},
               {"trace_sha256", out_->trace_sha256()},
               {"exchanges", exchanges_},
               {"modules", mods},
               {"chain",
                {{"displacement_m", {d.x(), d.y(), d.z()}},
                 {"distance_m", d.norm()},
                 {"speed_m_s", sim_s > 0 ? d.norm() / sim_s : 0.0}}},
               {"exit_code", r.exit_code},
               {"stopped_by", r.message.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.message)}};
  out_->write_summary(r.summary);
  if (opt_.observer) opt_.observer->finished(r.summary);
  return r;
}

}  // namespace

RunResult run_scene(const Scene& scene, const RunOptions& options, std::vector<ServoCommand>* record) {
  signal(SIGPIPE, SIG_IGN);
  Server server(scene, options, record);
  return server.run();
}

double replay_physics(const Scene& scene, const std::vector<ServoCommand>& commands, std::string* trace_sha256) {
  World world(scene.world);
  Sha256 sha;
  TraceClock trace_clock(scene);
  std::string row;
  row.reserve(1 << 14);
  const std::string header = world.trace_header();
  sha.update(header.data(), header.size());
  auto write = [&](const std::string& s) { sha.update(s.data(), s.size()); };
  const auto wall0 = Clock::now();
  const int64_t end_us = std::llround(scene.duration_s * 1e6);
  const int substeps = static_cast<int>(scene.tick_us / world.dt_us());
  size_t next = 0;
  trace_clock.maybe_write(world, &row, write);
  for (int64_t t = 0; t < end_us; t += scene.tick_us) {
    for (; next < commands.size() && commands[next].t_us <= t; ++next) {
      const ServoCommand& c = commands[next];
      world.set_servo_enabled(c.module, c.servo, c.enabled);
      if (c.enabled) world.set_servo_setpoint(c.module, c.servo, c.rad);
    }
    for (int k = 0; k < substeps; ++k) {
      world.step();
      trace_clock.maybe_write(world, &row, write);
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
  if (trace_sha256) *trace_sha256 = sha.hex();
  return wall;
}

}  // namespace chainsim
