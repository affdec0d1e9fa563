#include "chainsim/view_command.h"

#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "viewer/headless_chromium.h"
#include "cosim/lockstep_server.h"
#include "testing/run_compare.h"
#include "output/run_reader.h"
#include "viewer/viewer_page.h"

extern char** environ;

namespace chainsim {

namespace fs = std::filesystem;

namespace {

constexpr int kExitFailed = kExitInternal;
constexpr int kChromiumTimeoutS = 90;

bool write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << text;
  return static_cast<bool>(f.flush());
}

std::string tail_of(const fs::path& p, size_t n) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  const std::string t = s.str();
  return t.size() > n ? "..." + t.substr(t.size() - n) : t;
}

int render_png(const ViewArgs& a, const std::string& page) {
  const std::string chromium_program = find_chromium();
  if (chromium_program.empty()) {
    std::fprintf(stderr,
                 "chainsim: view --png needs Chromium, which is not installed: install the Debian package "
                 "'chromium' (apt-get install chromium; tools/setup.sh does), or set CHAINSIM_CHROMIUM\n");
    return kExitBadInput;
  }
  int w = 0, h = 0;
  if (std::sscanf(a.size.c_str(), "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192) {
    std::fprintf(stderr, "chainsim: --size %s: expected WIDTHxHEIGHT, e.g. 960x540\n", a.size.c_str());
    return kExitBadInput;
  }
  char tmpl[] = "/tmp/chainsim-view-XXXXXX";
  if (!mkdtemp(tmpl)) {
    std::perror("chainsim: mkdtemp");
    return kExitFailed;
  }
  const fs::path tmp = tmpl;
  const fs::path html = tmp / "page.html", log = tmp / "chromium.log";
  if (!write_file(html, page)) {
    std::fprintf(stderr, "chainsim: cannot write %s\n", html.c_str());
    return kExitFailed;
  }
  char t[64];
  std::snprintf(t, sizeof t, "%.6g", a.png_time);
  const std::string url = "file://" + html.string() + "#t=" + t + "&hideui" + (a.hash.empty() ? "" : "&" + a.hash);
  // the page is ready once it is posed at the time and its meshes are drawn;
  // two animation frames later the picture is on the canvas
  static const char* kWhenReady = R"(new Promise((resolve, reject) => {
    const poll = () => {
      const v = window.chainsimViewer;
      if (v?.state.errors.length) return reject(new Error(v.state.errors.join('; ')));
      if (v?.state.ready) return requestAnimationFrame(() => requestAnimationFrame(() => resolve(true)));
      setTimeout(poll, 20);
    };
    poll();
  }))";
  // Ctrl-C or a kill ends the wait; the temporary folder is removed below
  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = [](int sig) { HeadlessChromium::interrupted = sig; };
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  int result = kExitOk;
  const char* stage = "starting Chromium";
  try {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kChromiumTimeoutS);
    std::vector<unsigned char> png;
    {
      HeadlessChromium chromium(chromium_program, tmp / "profile", log, w, h, deadline);
      stage = "opening the page";
      chromium.open(url);
      stage = "waiting for the page to be drawn";
      chromium.evaluate(kWhenReady);
      stage = "taking the screenshot";
      png = chromium.screenshot_png();
    }
    std::ofstream f(a.out, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
    if (!f.flush()) {
      std::fprintf(stderr, "chainsim: cannot write %s\n", a.out.c_str());
      result = kExitFailed;
    }
  } catch (const std::exception& e) {
    if (HeadlessChromium::interrupted)
      std::fprintf(stderr, "chainsim: view --png %s; no picture written\n", e.what());
    else
      std::fprintf(stderr, "chainsim: Chromium did not render %s (%s, limit %d s): %s; its output:\n%s\n",
                 url.c_str(), stage, kChromiumTimeoutS, e.what(), tail_of(log, 2000).c_str());
    result = kExitFailed;
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  if (HeadlessChromium::interrupted) result = kExitInterrupted;
  std::error_code ec;
  fs::remove_all(tmp, ec);
  return result;
}

}  // namespace

std::string find_chromium() {
  if (const char* c = std::getenv("CHAINSIM_CHROMIUM"); c && *c) return access(c, X_OK) == 0 ? c : "";
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (access(c, X_OK) == 0) return c;
  return "";
}

// the page of two runs: each run's replay data, labelled by its directory's
// name, and the comparison of `chainsim run --compare` (run_compare.h) when
// the runs can be compared (its absence is a warning, the page still shows both)
nlohmann::json compare_boot(const ViewArgs& a, nlohmann::json boot_a, std::vector<std::string>* warnings,
                            std::string* title) {
  nlohmann::json boot_b = replay_boot(a.other_dir, warnings);
  auto label = [](const std::string& dir) {
    const fs::path p = fs::path(dir).lexically_normal();
    return (p.filename().empty() ? p.parent_path().filename() : p.filename()).string();
  };
  std::string la = label(a.run_dir), lb = label(a.other_dir);
  if (la == lb) la += " (A)", lb += " (B)";
  nlohmann::json boot = {{"mode", "compare"}, {"labels", {la, lb}}};
  try {
    RunReader ra(a.run_dir), rb(a.other_dir);
    const CompareReport r = compare_runs(ra, rb, la, lb);
    boot["report"] = compare_json(r);
    boot["report_text"] = compare_text(r);
  } catch (const std::exception& e) {
    warnings->push_back(std::string("the runs are shown, but not compared channel by channel: ") + e.what());
  }
  *title = "chainsim: " + la + " vs " + lb;
  boot["a"] = std::move(boot_a);
  boot["b"] = std::move(boot_b);
  return boot;
}

int cmd_view(const ViewArgs& a) {
  std::string page;
  try {
    std::vector<std::string> warnings;
    nlohmann::json boot = replay_boot(a.run_dir, &warnings);
    std::string title = "chainsim: " + boot["scene"].value("scene", std::string("run"));
    if (!a.other_dir.empty()) boot = compare_boot(a, std::move(boot), &warnings, &title);
    for (const std::string& w : warnings) std::fprintf(stderr, "chainsim: warning: %s\n", w.c_str());
    page = viewer_page(boot, title);
  } catch (const ViewerError& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  if (a.png_time >= 0) {
    if (a.out.empty()) {
      std::fprintf(stderr, "chainsim: view --png needs --out FILE.png\n");
      return kExitBadInput;
    }
    return render_png(a, page);
  }
  const std::string out =
      a.out.empty() ? (fs::path(a.run_dir) / (a.other_dir.empty() ? "replay.html" : "compare.html")).string() : a.out;
  if (!write_file(out, page)) {
    std::fprintf(stderr, "chainsim: cannot write %s\n", out.c_str());
    return kExitFailed;
  }
  std::fprintf(stderr, "chainsim: wrote %s (%.1f MB); open it in a browser\n", out.c_str(), page.size() / 1e6);
  return kExitOk;
}

namespace {
ViewArgs g_view_args;
}  // namespace

Command add_view_command(CLI::App& app) {
  auto* view = app.add_subcommand("view", "write RUN_DIR/replay.html, a replay of a run that opens from disk "
                                          "(or, with --png, a picture of the scene at a time)");
  view->add_option("run_dir", g_view_args.run_dir, "run directory (of chainsim run --out)")->required()
      ->check(CLI::ExistingDirectory);
  view->add_option("other_run_dir", g_view_args.other_dir,
                   "a second run directory: RUN_DIR/compare.html shows the two side by side, plots overlaid, their "
                   "summaries' differences and where they first differ (docs/viewer.md)")
      ->check(CLI::ExistingDirectory);
  view->add_option("--png", g_view_args.png_time, "render a PNG of the scene at this time (s) with headless Chromium")
      ->check(CLI::NonNegativeNumber);
  view->add_option("--out,-o", g_view_args.out, "file to write (default RUN_DIR/replay.html; required with --png)");
  view->add_option("--size", g_view_args.size, "picture size WIDTHxHEIGHT (default 960x540)");
  view->add_option("--page-options", g_view_args.hash, "more options for the pictured page, e.g. follow=0");
  return {view, [] { return cmd_view(g_view_args); }};
}

}  // namespace chainsim
