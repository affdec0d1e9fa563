// The live view of `chainsim run --live`: an HTTP server on 127.0.0.1 that
// serves the viewer page and streams the run to it over a WebSocket (/ws) as
// it happens.
//
// The simulation loop calls the RunObserver methods; they only append to a
// bounded buffer under a mutex that the network thread holds just long
// enough to swap the buffer out (never during I/O). Rows that do not fit are
// dropped and counted, never waited for. The network thread sends batches
// every 40 ms; a page too slow to keep up loses rows (it is told how many),
// never bus events or the start and end. A page that connects late gets the
// run so far (up to a bounded history).
//
// Only the page it serves may read the run: a request must name the server
// in its Host (127.0.0.1:PORT or localhost:PORT), and a WebSocket upgrade
// must come with that page's Origin; anything else gets 403 with the reason
// (docs/viewer.md, "Live mode").
#pragma once

#include <memory>
#include <string>

#include "cosim/lockstep_server.h"

namespace chainsim {

class LiveView : public RunObserver {
 public:
  // binds 127.0.0.1:port (0: any free port) and starts the network thread;
  // throws std::runtime_error when it cannot listen
  LiveView(std::string page_html, int port);
  ~LiveView() override;
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  int port() const;
  std::string url() const;  // http://127.0.0.1:<port>/

  // before the run: wait up to timeout_s for a page to connect; true if one did
  bool wait_for_page(double timeout_s);
  // after the run: serve until a page has acknowledged `finished`, or, with no
  // page connected, grace_s have passed (a connected page gets up to 10 s more)
  void wait_until_seen(double grace_s);

  // RunObserver: copy into the bounded buffer, never block
  void started(const nlohmann::json& scene, const std::string& trace_header) override;
  void trace_row(const std::string& row) override;
  void bus_line(int64_t t_us, const char* line) override;
  // sent with the bus lines as "<t_us> log endpoint=E <line>"
  void module_log(int endpoint, int64_t t_us, const char* line) override;
  void finished(const nlohmann::json& summary) override;

  // a new run follows (`chainsim run --watch`): what is held of the last one
  // is dropped, and every open page is told to reload, why with it, so that
  // it shows the next run from its start
  void restart(const std::string& why);

  // counters, for tests and the end-of-run message
  struct Stats {
    uint64_t rows_in = 0, rows_dropped = 0, pages = 0, messages_sent = 0;
    bool acked = false;
  };
  Stats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// `chainsim run --live`: the server with the live page; prints its URL on
// stderr, then waits up to wait_s for a page to connect. Null, after saying
// why on stderr, when the viewer bundle is missing or the port is taken.
std::unique_ptr<LiveView> start_live_view(const std::string& scene_name, int port, double wait_s);

}  // namespace chainsim
