// A run's processes and links. See endpoints.h.
#include "cosim/endpoints.h"

#include <sys/prctl.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cosim/program_params.h"
#include "cosim/socket_dir.h"
#include "text/number_text.h"

namespace chainsim {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kTerminateGraceMs = 1000;

// the last non-empty line of a module's output before the backtrace its HAL
// printed, if any (the backtrace's addresses differ from run to run; a fault
// message, which a design search records, must not)
std::string last_line_of(const std::string& path, bool* backtrace) {
  std::ifstream in(path);
  std::string line, last;
  *backtrace = false;
  while (std::getline(in, line)) {
    if (line.rfind(CS_NOTICE_BACKTRACE, 0) == 0) {
      *backtrace = true;
      break;
    }
    if (!line.empty()) last = line;
  }
  return last;
}

// whether the file at path has a line containing text
bool file_has(const std::string& path, const char* text) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

Endpoints::Endpoints(const Scene& scene, const RunOptions& options, RunOutput* out,
                     asio::io_context* io)
    : scene_(scene), opt_(options), out_(out), io_(io) {
  // what the modules start stays this process's to end (shutdown), and the
  // server's open files are not theirs to reopen through /proc/PID/fd: a
  // process that is not dumpable has its /proc entries owned by root
  become_subreaper();
  prctl(PR_SET_DUMPABLE, 0);
  const int n = static_cast<int>(scene.modules.size());
  for (int m = 0; m <= n; ++m) {
    const SceneModule& sm = m < n ? scene.modules[m] : scene.central;
    auto e = std::make_unique<Endpoint>();
    e->index = m;
    e->type = m < n ? sm.type : "central";
    e->program = sm.firmware;
    e->target = sm.target;
    e->params = sm.params;
    ep_.push_back(std::move(e));
  }
}

Endpoints::~Endpoints() {
  if (socket_dir_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(socket_dir_, ec);
}

std::vector<std::string> endpoint_types(const Scene& scene) {
  std::vector<std::string> types = scene.chain_types();
  types.push_back("central");
  return types;
}

std::string Endpoints::name_of(const Endpoint& e) const {
  const uint32_t pid = e.pid ? e.pid : (e.proc.pid() > 0 ? static_cast<uint32_t>(e.proc.pid()) : 0);
  std::string s = (e.index == size() - 1 ? "central control" : "module " + std::to_string(e.index)) +
                  " (" + e.type;
  if (pid) s += ", pid " + std::to_string(pid);
  return s + ")";
}

std::string program_path(const std::string& program, const std::string& dirs) {
  if (program.find('/') != std::string::npos) return program;
  for (size_t b = 0; b < dirs.size();) {
    const size_t e = std::min(dirs.find(':', b), dirs.size());
    const std::string p = dirs.substr(b, e - b) + "/" + program;
    if (e > b && access(p.c_str(), X_OK) == 0) return p;
    b = e + 1;
  }
  return executable_dir() + "/" + program;
}

std::string pic_hex_path(const std::string& program, const std::string& dirs) {
  auto is_file = [](const std::string& p) {
    struct stat st {};
    return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  };
  if (program.find('/') != std::string::npos) return is_file(program + ".hex") ? program + ".hex" : "";
  for (size_t b = 0; b < dirs.size();) {
    const size_t e = std::min(dirs.find(':', b), dirs.size());
    const std::string p = dirs.substr(b, e - b) + "/" + program + ".hex";
    if (e > b && is_file(p)) return p;
    b = e + 1;
  }
  for (const std::string& p : {executable_dir() + "/" + program + ".hex", executable_dir() + "/../pic/" + program + ".hex"})
    if (is_file(p)) return p;
  return "";
}

std::string pic_hex_missing(const std::string& program, const std::string& dirs) {
  const std::string hex = program + ".hex";
  if (program.find('/') != std::string::npos)
    return hex + " not found: build it for the PIC (-DCHAINSIM_PIC=ON in its CMake project, docs/pic-in-the-loop.md)";
  return hex + " not found (looked in " + (dirs.empty() ? "" : "--firmware-dir " + dirs + ", then ") + executable_dir() +
         " and " + executable_dir() + "/../pic): build the shipped programs with tools/pic-build.sh, your own with "
         "-DCHAINSIM_PIC=ON (docs/pic-in-the-loop.md)";
}

std::string pic_module_program() { return executable_dir() + "/chainsim-pic"; }

void Endpoints::start() {
  remove_stale_socket_dirs();  // of servers killed outright, which could not remove their own
  socket_dir_ = make_socket_dir();
  socket_path_ = socket_dir_ + "/chainsim.sock";
  acceptor_ = std::make_unique<asio::local::stream_protocol::acceptor>(
      *io_, asio::local::stream_protocol::endpoint(socket_path_));
  chmod(socket_path_.c_str(), 0600);
  for (auto& ep : ep_) {
    Endpoint& e = *ep;
    const bool pic = e.target == Target::Pic;
    const std::string hex = pic ? pic_hex_path(e.program, opt_.firmware_dir) : "";
    if (pic && hex.empty())
      throw std::runtime_error("program for " + name_of(e) + " on the PIC: " + pic_hex_missing(e.program, opt_.firmware_dir));
    const std::string prog = pic ? pic_module_program() : program_path(e.program, opt_.firmware_dir);
    e.attached = opt_.attach.count(e.index) > 0;
    if (e.attached) {
      say(opt_, "waiting for " + name_of(e) + " started by hand:\n  CHAINSIM_SOCKET=" + socket_path_ +
                    " CHAINSIM_MODULE_INDEX=" + std::to_string(e.index) + " CHAINSIM_MODULE_TYPE=" +
                    e.type + (pic ? " " + prog + " " + hex : " gdb " + prog));
      continue;
    }
    if (access(prog.c_str(), X_OK) != 0)
      throw std::runtime_error("program for " + name_of(e) + " not found or not executable: " + prog +
                               (pic ? " (chainsim was built without libgpsim: install gpsim-dev and libglib2.0-dev, "
                                      "then build again)" : ""));
    ChildSpec spec;
    spec.program = prog;
    spec.env = {"CHAINSIM_SOCKET=" + socket_path_, "CHAINSIM_MODULE_INDEX=" + std::to_string(e.index),
                "CHAINSIM_MODULE_TYPE=" + e.type};
    if (pic) {
      e.pic_stats = out_->module_file(e.index, "pic.json");
      spec.args = {hex};
      spec.env.push_back("CHAINSIM_PIC_STATS=" + e.pic_stats);
      spec.env.push_back("CHAINSIM_PIC_CPU_BUDGET_US=" + std::to_string(scene_.pic.cpu_budget_us));
      spec.env.push_back("CHAINSIM_PIC_STALL_MS=" + std::to_string(scene_.pic.stall_ms));
      spec.env.push_back(std::string("CHAINSIM_PIC_ON_OVERRUN=") + (opt_.overrun_warn ? "warn" : "stop"));
    }
    spec.stdout_path = out_->module_file(e.index, "out");
    e.proc.spawn(spec);
  }
}

void Endpoints::on_hello(std::shared_ptr<ModuleLink> link) {
  // those dropped already are let go: a peer connecting and closing again
  // and again costs nothing that grows
  std::erase_if(pending_, [](const std::shared_ptr<ModuleLink>& l) { return !l->open(); });
  pending_.push_back(link);
  link->async_receive([this, link](const std::string& err) {
    if (!link->open()) return;  // dropped at the end of the handshake
    // a peer that breaks the handshake is dropped; the module it should have
    // been is then reported when it does not connect in time
    if (!err.empty() || link->received().type != CS_MSG_HELLO) {
      say(opt_, "dropped a connection: " +
                    (err.empty() ? std::string("it sent ") + cs_msg_name(link->received().type) + " instead of HELLO"
                                 : err));
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
      say(opt_, "rejected a connection: " + why);
      return;
    }
    Endpoint& e = *ep_[h.module_index];
    e.pid = h.pid;
    reply.type = CS_MSG_WELCOME;
    cs_welcome& w = reply.u.welcome;
    w.version = CS_VERSION;
    w.module_index = h.module_index;
    w.tick_us = static_cast<uint32_t>(scene_.tick_us);
    w.seed = scene_.world.seed;
    for (const auto& [k, v] : e.params) {
      if (w.n_params >= CS_PARAMS_MAX) break;
      std::snprintf(w.params[w.n_params].name, CS_PARAM_NAME_MAX, "%s", k.c_str());
      w.params[w.n_params].value = v;
      ++w.n_params;
    }
    if (!link->send(reply).empty()) return;
    e.link = link;
  });
}

bool Endpoints::handshake(const FaultHandler& on_fault, const int* interrupted) {
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
    if (*interrupted) return false;
    for (auto& ep : ep_) {
      Endpoint& e = *ep;
      if (e.link || !e.fault.empty() || e.attached) continue;
      if (e.proc.poll()) {
        if (!on_fault(e, "ended before connecting: " + e.proc.poll()->text())) return false;
      } else if (Clock::now() > deadline) {
        if (!on_fault(e, "did not connect within " + fixed_text(opt_.module_timeout_s, 1) + " s"))
          return false;
      }
    }
    io_->run_one_for(std::chrono::milliseconds(20));
  }
  acceptor_->close();
  drop_pending("it sent no HELLO before every module had connected");
  return true;
}

void Endpoints::drop_pending(const std::string& why) {
  for (const auto& link : pending_) {
    bool adopted = false;
    for (const auto& e : ep_) adopted |= e->link == link;
    if (adopted || !link->open()) continue;
    if (!why.empty()) say(opt_, "dropped a connection: " + why);
    link->close();
  }
  io_->poll();  // their reads end (aborted) while the links still exist
  pending_.clear();
}

std::string Endpoints::describe_end(Endpoint& e, const std::string& what, int64_t now_us) {
  std::string s = name_of(e) + " " + what;
  if (!e.attached && e.proc.pid() > 0) {
    // a process that closed its socket is on its way out: give it a moment to be reaped
    const bool dying = what.rfind("closed its socket", 0) == 0;
    if (const auto& st = e.proc.wait_for(dying ? 1000 : 0)) {
      if (dying) s = name_of(e) + " ended: " + st->text();
      else if (what.find(st->text()) == std::string::npos) s += " (then ended: " + st->text() + ")";
    }
    const std::string out = out_->module_file(e.index, "out");
    bool backtrace = false;
    const std::string last = last_line_of(out, &backtrace);
    if (!last.empty()) s += "; its last output: \"" + last + "\"";
    // named inside the run directory: the same text wherever the run is
    if (backtrace) s += "; backtrace in " + out.substr(out_->dir().size() + 1);
  }
  return s + " at t=" + fixed_text(now_us * 1e-6, 6) + " s";
}

std::string Endpoints::silence_cause(const Endpoint& e) const {
  if (!e.attached && file_has(out_->module_file(e.index, "out"), CS_NOTICE_WAIT_SPINS))
    return "busy in hal_wait_event_ms, which returns at once while an I2C frame waits unread";
  return "hung, or busy without a HAL wait";
}

void Endpoints::cut_off(Endpoint& e) {
  if (e.link) e.link->close();
  if (!e.attached) e.proc.terminate(kTerminateGraceMs);
}

void Endpoints::shutdown(bool finished) {
  cs_msg bye{};
  bye.type = CS_MSG_SHUTDOWN;
  std::snprintf(bye.u.shutdown.reason, CS_REASON_MAX, "%s", finished ? "run finished" : "run stopped");
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
  // what a module left running: in its process group (a fork), or, having
  // left the group (setsid), adopted by this process (become_subreaper)
  for (auto& e : ep_)
    if (!e->attached && e->proc.pid() > 0) kill(-e->proc.pid(), SIGKILL);
  const int orphans = end_adopted_orphans();
  if (orphans > 0 && !opt_.quiet)
    std::fprintf(stderr, "chainsim: %d process%s a module left behind ended\n", orphans, orphans == 1 ? "" : "es");
  if (acceptor_) acceptor_->close();
  drop_pending("");  // a handshake that a fault or a signal cut short
  std::error_code ec;
  std::filesystem::remove_all(socket_dir_, ec);
  socket_dir_.clear();
}

}  // namespace chainsim
