#include <utility>  // before Boost.Asio: Boost 1.74 with GCC 12 in C++20 needs it

#include "viewer/live_view.h"

#include "viewer/viewer_page.h"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <future>
#include <initializer_list>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

namespace chainsim {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Msg = std::shared_ptr<const std::string>;

namespace {

constexpr size_t kInputCap = 8u << 20;     // sim -> network buffer (bytes); rows past it are dropped
constexpr size_t kHistoryCap = 64u << 20;  // rows kept for pages that connect late
constexpr size_t kPageCap = 4u << 20;      // bytes queued for one page before its rows are dropped
constexpr auto kFlushEvery = std::chrono::milliseconds(40);

Msg make_msg(const nlohmann::json& j) { return std::make_shared<const std::string>(j.dump()); }

// a header's value for a message: at most 80 characters, anything but
// printable ASCII as \xNN
std::string shown(beast::string_view v) {
  std::string o;
  for (size_t i = 0; i < v.size() && i < 80; ++i) {
    const unsigned char c = static_cast<unsigned char>(v[i]);
    if (c >= 0x20 && c < 0x7f && c != '\'') {
      o += static_cast<char>(c);
    } else {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%02x", c);
      o += b;
    }
  }
  return v.size() > 80 ? o + "..." : o;
}

std::string lower(beast::string_view v) {
  std::string o(v);
  for (char& c : o) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return o;
}

}  // namespace

struct LiveView::Impl {
  struct Page;
  std::string page_html;
  asio::io_context io;
  tcp::acceptor acceptor{io};
  asio::steady_timer timer{io};
  std::thread thread;
  int port = 0;
  bool said_refused = false;  // the first refused request is said on stderr, the others not

  // filled by the simulation thread
  std::mutex in_mu;
  std::string in_rows, in_bus;
  std::optional<std::string> in_started, in_finished, in_restart;
  uint64_t in_dropped = 0;
  uint64_t rows_in = 0, rows_dropped = 0;  // whole run

  // network thread only
  Msg started_msg, finished_msg;
  std::deque<Msg> row_history;
  size_t row_history_bytes = 0;
  std::vector<Msg> bus_history;
  std::set<std::shared_ptr<Page>> pages;

  // shared with the waiting threads
  mutable std::mutex st_mu;
  std::condition_variable st_cv;
  Stats st;
  int open_pages = 0;

  // one WebSocket client
  struct Page : std::enable_shared_from_this<Page> {
    Impl& impl;
    websocket::stream<beast::tcp_stream> ws;
    beast::flat_buffer rbuf;
    std::deque<Msg> queue;
    size_t queued = 0;
    uint64_t gap_rows = 0;
    bool writing = false, open = false;

    Page(Impl& i, beast::tcp_stream&& s) : impl(i), ws(std::move(s)) {}

    void accept(http::request<http::string_body> req) {
      ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
      ws.text(true);
      ws.async_accept(req, [self = shared_from_this()](beast::error_code ec) {
        if (ec) return;
        self->open = true;
        self->impl.on_open(self);
        self->read();
      });
    }
    void read() {
      ws.async_read(rbuf, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (ec) return self->impl.on_close(self);
        const std::string text = beast::buffers_to_string(self->rbuf.data());
        self->rbuf.consume(self->rbuf.size());
        if (text.find("\"ack\"") != std::string::npos) self->impl.on_ack();
        self->read();
      });
    }
    // rows (row_count > 0) may be dropped when the page is behind; nothing else is
    void send(const Msg& m, uint64_t row_count = 0) {
      if (!open) return;
      if (row_count && queued > kPageCap) {
        gap_rows += row_count;
        return;
      }
      if (row_count && gap_rows) {
        push(make_msg({{"type", "gap"}, {"rows", gap_rows}}));
        gap_rows = 0;
      }
      push(m);
    }
    void push(const Msg& m) {
      queue.push_back(m);
      queued += m->size();
      if (!writing) write();
    }
    void write() {
      writing = true;
      ws.async_write(asio::buffer(*queue.front()), [self = shared_from_this()](beast::error_code ec, size_t) {
        self->queued -= self->queue.front()->size();
        self->queue.pop_front();
        self->writing = false;
        if (ec) return self->impl.on_close(self);
        self->impl.count_sent();
        if (!self->queue.empty()) self->write();
      });
    }
  };

  // a plain HTTP request: the page, or the upgrade to /ws
  struct Http : std::enable_shared_from_this<Http> {
    Impl& impl;
    beast::tcp_stream stream;
    beast::flat_buffer buf;
    http::request<http::string_body> req;
    http::response<http::string_body> res;
    Http(Impl& i, tcp::socket s) : impl(i), stream(std::move(s)) {}
    void start() {
      stream.expires_after(std::chrono::seconds(30));
      http::async_read(stream, buf, req, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (!ec) self->handle();
      });
    }
    void handle() {
      const std::string target(req.target());
      if (const std::string why = impl.refusal(req); !why.empty()) return refuse(why);
      if (websocket::is_upgrade(req) && target == "/ws") {
        stream.expires_never();
        std::make_shared<Page>(impl, std::move(stream))->accept(std::move(req));
        return;
      }
      const bool page = req.method() == http::verb::get && (target == "/" || target.rfind("/?", 0) == 0 ||
                                                             target == "/index.html");
      res.version(req.version());
      res.keep_alive(false);
      res.result(page ? http::status::ok : http::status::not_found);
      res.set(http::field::content_type, page ? "text/html; charset=utf-8" : "text/plain");
      res.set(http::field::cache_control, "no-store");
      res.body() = page ? impl.page_html : "not found: the live view is at /\n";
      res.prepare_payload();
      send();
    }
    // 403 with the reason, and nothing of the run
    void refuse(const std::string& why) {
      res.version(req.version());
      res.keep_alive(false);
      res.result(http::status::forbidden);
      res.set(http::field::content_type, "text/plain; charset=utf-8");
      res.set(http::field::cache_control, "no-store");
      res.body() = "forbidden: " + why + "\n";
      res.prepare_payload();
      send();
    }
    void send() {
      http::async_write(stream, res, [self = shared_from_this()](beast::error_code, size_t) {
        beast::error_code ignored;
        self->stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
      });
    }
  };

  // Only the page this server serves may read the run: a request must name
  // this server in its Host (127.0.0.1:PORT or localhost:PORT), which a page
  // of another site that had its own name resolved to 127.0.0.1 (DNS
  // rebinding) cannot; a WebSocket upgrade must come from this server's own
  // page, its Origin http://127.0.0.1:PORT or http://localhost:PORT, which a
  // page of another site that opens a WebSocket here cannot fake (browsers
  // set Origin themselves). An upgrade with no Origin is refused too: every
  // browser sends one, and the live page is opened in a browser. A plain
  // request may have no Origin (a browser sends none when it opens the page),
  // but one that has another is refused as well. Returns why a request is
  // refused, "" when it is not.
  std::string refusal(const http::request<http::string_body>& r) {
    const std::string p = std::to_string(port);
    auto one_of = [&](const std::string& v, std::initializer_list<std::string> names) {
      for (const std::string& n : names)
        if (v == n + ":" + p || (port == 80 && v == n)) return true;  // a browser leaves out port 80
      return false;
    };
    std::string why;
    const auto host = r.find(http::field::host);
    const auto origin = r.find(http::field::origin);
    if (r.count(http::field::host) != 1) {
      why = r.count(http::field::host) == 0 ? "no Host header" : "more than one Host header";
    } else if (!one_of(lower(host->value()), {"127.0.0.1", "localhost"})) {
      why = "Host '" + shown(host->value()) + "' is not this live view (127.0.0.1:" + p + " or localhost:" + p + ")";
    } else if (r.count(http::field::origin) > 1) {
      why = "more than one Origin header";
    } else if (origin == r.end()) {
      if (websocket::is_upgrade(r)) why = "a WebSocket without an Origin header: only the live page may connect";
    } else if (!one_of(std::string(origin->value()), {"http://127.0.0.1", "http://localhost"})) {
      why = "Origin '" + shown(origin->value()) + "' is not the live page (http://127.0.0.1:" + p +
            " or http://localhost:" + p + ")";
    }
    if (!why.empty() && !said_refused) {
      said_refused = true;
      std::fprintf(stderr, "chainsim: live view: refused a request: %s (further refusals are not said)\n", why.c_str());
    }
    return why;
  }

  void accept_loop() {
    acceptor.async_accept([this](beast::error_code ec, tcp::socket s) {
      if (ec) return;
      std::make_shared<Http>(*this, std::move(s))->start();
      accept_loop();
    });
  }

  void on_open(const std::shared_ptr<Page>& p) {
    pages.insert(p);
    {
      std::lock_guard<std::mutex> l(st_mu);
      ++st.pages;
      ++open_pages;
    }
    st_cv.notify_all();
    // the run so far
    if (started_msg) p->send(started_msg);
    for (const Msg& m : row_history) p->send(m);
    for (const Msg& m : bus_history) p->send(m);
    if (finished_msg) p->send(finished_msg);
  }
  void on_close(const std::shared_ptr<Page>& p) {
    if (!p->open) return;
    p->open = false;
    pages.erase(p);
    {
      std::lock_guard<std::mutex> l(st_mu);
      --open_pages;
    }
    st_cv.notify_all();
  }
  void on_ack() {
    {
      std::lock_guard<std::mutex> l(st_mu);
      st.acked = true;
    }
    st_cv.notify_all();
  }
  void count_sent() {
    std::lock_guard<std::mutex> l(st_mu);
    ++st.messages_sent;
  }

  // every 40 ms: take what the simulation produced and send it
  void flush_loop() {
    timer.expires_after(kFlushEvery);
    timer.async_wait([this](beast::error_code ec) {
      if (ec) return;
      flush();
      flush_loop();
    });
  }
  void flush() {
    std::string rows, bus;
    std::optional<std::string> started, finished, restart;
    uint64_t dropped = 0;
    {
      std::lock_guard<std::mutex> l(in_mu);
      restart.swap(in_restart);
      rows.swap(in_rows);
      bus.swap(in_bus);
      started.swap(in_started);
      finished.swap(in_finished);
      std::swap(dropped, in_dropped);
    }
    if (restart) {  // before the next run's start, which came after it
      started_msg.reset();
      finished_msg.reset();
      row_history.clear();
      row_history_bytes = 0;
      bus_history.clear();
      broadcast(make_msg({{"type", "reload"}, {"why", *restart}}));
    }
    if (started) broadcast(started_msg = std::make_shared<const std::string>(std::move(*started)));
    if (!rows.empty()) {
      const uint64_t n = static_cast<uint64_t>(std::count(rows.begin(), rows.end(), '\n'));
      const Msg m = make_msg({{"type", "rows"}, {"csv", rows}});
      row_history.push_back(m);
      row_history_bytes += m->size();
      while (row_history_bytes > kHistoryCap && row_history.size() > 1) {
        row_history_bytes -= row_history.front()->size();
        row_history.pop_front();
      }
      broadcast(m, n);
    }
    if (dropped) broadcast(make_msg({{"type", "gap"}, {"rows", dropped}}));
    if (!bus.empty()) {
      bus_history.push_back(make_msg({{"type", "bus"}, {"lines", bus}}));
      broadcast(bus_history.back());
    }
    if (finished) broadcast(finished_msg = std::make_shared<const std::string>(std::move(*finished)));
  }
  void broadcast(const Msg& m, uint64_t rows = 0) {
    for (const auto& p : std::vector<std::shared_ptr<Page>>(pages.begin(), pages.end())) p->send(m, rows);
  }
};

LiveView::LiveView(std::string page_html, int port) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  I.page_html = std::move(page_html);
  beast::error_code ec;
  const tcp::endpoint ep(asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port));
  I.acceptor.open(ep.protocol(), ec);
  if (!ec) I.acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) I.acceptor.bind(ep, ec);
  if (!ec) I.acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error("live view: cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + ec.message());
  I.port = I.acceptor.local_endpoint().port();
  I.accept_loop();
  I.flush_loop();
  I.thread = std::thread([&I] { I.io.run(); });
}

LiveView::~LiveView() {
  Impl& I = *impl_;
  asio::post(I.io, [&I] {
    I.flush();  // whatever is still buffered
    beast::error_code ec;
    I.acceptor.close(ec);
  });
  // let the last messages go out (at most half a second), then stop
  for (int i = 0; i < 25; ++i) {
    auto busy = std::make_shared<std::promise<bool>>();
    std::future<bool> f = busy->get_future();
    asio::post(I.io, [&I, busy] {
      bool b = false;
      for (const auto& p : I.pages) b = b || p->writing;
      busy->set_value(b);
    });
    if (f.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready || !f.get()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  I.io.stop();
  if (I.thread.joinable()) I.thread.join();
  I.pages.clear();
}

int LiveView::port() const { return impl_->port; }
std::string LiveView::url() const { return "http://127.0.0.1:" + std::to_string(impl_->port) + "/"; }

bool LiveView::wait_for_page(double timeout_s) {
  std::unique_lock<std::mutex> l(impl_->st_mu);
  return impl_->st_cv.wait_for(l, std::chrono::duration<double>(timeout_s), [&] { return impl_->st.pages > 0; });
}

void LiveView::wait_until_seen(double grace_s) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto grace = std::chrono::duration<double>(grace_s);
  const auto hard = grace + std::chrono::seconds(10);
  std::unique_lock<std::mutex> l(impl_->st_mu);
  for (;;) {
    const auto waited = std::chrono::steady_clock::now() - t0;
    if (impl_->st.acked || waited > hard || (waited > grace && impl_->open_pages == 0)) return;
    impl_->st_cv.wait_for(l, std::chrono::milliseconds(100));
  }
}

void LiveView::started(const nlohmann::json& scene, const std::string& trace_header) {
  // the environment's mesh files travel with the scene, as in a replay page
  std::string m = nlohmann::json{{"type", "started"},
                                 {"scene", scene},
                                 {"header", trace_header},
                                 {"files", environment_files(scene, "", nullptr)}}
                      .dump();
  std::lock_guard<std::mutex> l(impl_->in_mu);
  impl_->in_started = std::move(m);
}

void LiveView::trace_row(const std::string& row) {
  std::lock_guard<std::mutex> l(impl_->in_mu);
  ++impl_->rows_in;
  if (impl_->in_rows.size() + row.size() > kInputCap) {
    ++impl_->in_dropped;
    ++impl_->rows_dropped;
    return;
  }
  impl_->in_rows += row;
}

void LiveView::bus_line(int64_t t_us, const char* line) {
  std::lock_guard<std::mutex> l(impl_->in_mu);
  if (impl_->in_bus.size() > kInputCap && std::strncmp(line, "fault", 5) != 0) return;
  impl_->in_bus += std::to_string(t_us);
  impl_->in_bus += ' ';
  impl_->in_bus += line;
  impl_->in_bus += '\n';
}

void LiveView::module_log(int endpoint, int64_t t_us, const char* line) {
  std::lock_guard<std::mutex> l(impl_->in_mu);
  if (impl_->in_bus.size() > kInputCap) return;
  impl_->in_bus += std::to_string(t_us) + " log endpoint=" + std::to_string(endpoint) + " " + line + "\n";
}

void LiveView::finished(const nlohmann::json& summary) {
  std::string m = nlohmann::json{{"type", "finished"}, {"summary", summary}}.dump();
  std::lock_guard<std::mutex> l(impl_->in_mu);
  impl_->in_finished = std::move(m);
}

void LiveView::restart(const std::string& why) {
  {
    std::lock_guard<std::mutex> l(impl_->in_mu);
    impl_->in_rows.clear();
    impl_->in_bus.clear();
    impl_->in_started.reset();
    impl_->in_finished.reset();
    impl_->in_dropped = 0;
    impl_->in_restart = why;
  }
  std::lock_guard<std::mutex> l(impl_->st_mu);
  impl_->st.acked = false;
}

LiveView::Stats LiveView::stats() const {
  Stats s;
  {
    std::lock_guard<std::mutex> l(impl_->st_mu);
    s = impl_->st;
  }
  std::lock_guard<std::mutex> l(impl_->in_mu);
  s.rows_in = impl_->rows_in;
  s.rows_dropped = impl_->rows_dropped;
  return s;
}

std::unique_ptr<LiveView> start_live_view(const std::string& scene_name, int port, double wait_s) {
  std::unique_ptr<LiveView> live;
  try {
    live = std::make_unique<LiveView>(viewer_page({{"mode", "live"}}, "chainsim live: " + scene_name), port);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return nullptr;
  }
  std::fprintf(stderr, "chainsim: live view at %s\n", live->url().c_str());
  if (wait_s > 0) {
    std::fprintf(stderr, "chainsim: waiting up to %.0f s for a page to connect\n", wait_s);
    if (!live->wait_for_page(wait_s)) std::fprintf(stderr, "chainsim: no page connected; running anyway\n");
  }
  return live;
}

}  // namespace chainsim
