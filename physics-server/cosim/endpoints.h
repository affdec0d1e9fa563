// The processes of a run and their links: one endpoint per module plus the
// central control (the last one). Spawns them with their environment in a
// private socket directory, accepts their connections and checks each HELLO,
// says in words how one ended, and ends them all.
#pragma once

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it
#include <boost/asio.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cosim/child_process.h"
#include "cosim/module_link.h"
#include "cosim/run_options.h"
#include "output/run_output.h"
#include "scene/scene.h"

namespace chainsim {

struct Endpoint {
  int index = 0;
  std::string type;                 // module type, or "central"
  std::string program;              // as the scene names it
  Target target = Target::Native;   // pic: chainsim-pic runs PROGRAM.hex
  std::string pic_stats;            // pic: where chainsim-pic leaves its figures
  std::map<std::string, int32_t> params;
  ChildProcess proc;
  bool attached = false;            // started by hand (--attach)
  std::shared_ptr<ModuleLink> link; // after its HELLO was accepted
  uint32_t pid = 0;                 // as its HELLO said
  std::string fault;                // empty while healthy
  bool replied = false;             // this tick
  std::string reply_error;          // this tick
};

// the type of each endpoint: the modules', then "central"
std::vector<std::string> endpoint_types(const Scene& scene);

// where a program a scene names runs from: a path as given; a bare name from
// the first of firmware_dir's directories (DIR[:DIR...]) that holds it, else
// beside chainsim
std::string program_path(const std::string& program, const std::string& firmware_dir);

// where a program runs from on the PIC: PROGRAM.hex (with its .cod, .map and
// .pic.json), looked for as program_path looks, then in the tree's PIC build
// (build/pic, tools/pic-build.sh); "" when there is none
std::string pic_hex_path(const std::string& program, const std::string& firmware_dir);
// why a program's .hex was not found, and how to build it
std::string pic_hex_missing(const std::string& program, const std::string& firmware_dir);
// the module process that runs a .hex (chainsim-pic, beside chainsim)
std::string pic_module_program();

class Endpoints {
 public:
  // on_fault(e, what): e failed as `what` says; returns true if the run goes on
  using FaultHandler = std::function<bool(Endpoint& e, const std::string& what)>;

  Endpoints(const Scene& scene, const RunOptions& options, RunOutput* out,
            boost::asio::io_context* io);
  ~Endpoints();
  Endpoints(const Endpoints&) = delete;
  Endpoints& operator=(const Endpoints&) = delete;

  int size() const { return static_cast<int>(ep_.size()); }
  Endpoint& operator[](int i) { return *ep_[i]; }
  const Endpoint& operator[](int i) const { return *ep_[i]; }

  // "module 3 (rotation, pid 4242)" or "central control (central, pid ...)"
  std::string name_of(const Endpoint& e) const;

  // the private socket, then every process (those started by hand are
  // announced with the command to start them); throws std::runtime_error
  // naming a program that is missing
  void start();
  // accept until every endpoint has said HELLO or failed; false if a fault
  // stopped the run or *interrupted became non-zero
  bool handshake(const FaultHandler& on_fault, const int* interrupted);
  // e's name, what happened, how its process ended if it did, its last
  // output line, where its backtrace is if it printed one, and the
  // simulated time
  std::string describe_end(Endpoint& e, const std::string& what, int64_t now_us);
  // why e may not have answered in time, from what its process printed
  std::string silence_cause(const Endpoint& e) const;
  // after a fault: e's link closed, its process ended
  void cut_off(Endpoint& e);
  // SHUTDOWN to every open link, a moment to exit, then every process ended
  // and the socket directory removed
  void shutdown(bool finished);

 private:
  void on_hello(std::shared_ptr<ModuleLink> link);
  // closes every connection that is no endpoint's (a peer that sent half a
  // HELLO and fell silent), saying why (unless why is empty)
  void drop_pending(const std::string& why);

  const Scene& scene_;
  const RunOptions& opt_;
  RunOutput* out_;
  boost::asio::io_context* io_;
  std::vector<std::unique_ptr<Endpoint>> ep_;
  std::unique_ptr<boost::asio::local::stream_protocol::acceptor> acceptor_;
  std::vector<std::shared_ptr<ModuleLink>> pending_;  // every connection accepted in the handshake
  std::string socket_dir_, socket_path_;
};

}  // namespace chainsim
