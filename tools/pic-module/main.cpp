// chainsim-pic: a module process that runs the board's own binary. The
// program's .hex (with its .cod, .map and .pic.json beside it) runs
// instruction by instruction in gpsim, in lockstep with the physics server,
// which spawns it for a module whose target is pic (docs/pic-in-the-loop.md).
//
//   chainsim-pic PROGRAM.hex                      as a module: CHAINSIM_SOCKET,
//                                                 CHAINSIM_MODULE_INDEX, CHAINSIM_MODULE_TYPE
//   chainsim-pic --chainsim-params PROGRAM.hex    the parameters its flash declares
//
// Environment of a run (set by the server): CHAINSIM_PIC_STATS (where the
// measured figures go, JSON, at the end), CHAINSIM_PIC_CPU_BUDGET_US,
// CHAINSIM_PIC_ON_OVERRUN (stop or warn), CHAINSIM_PIC_STALL_MS.
// Exit codes: 0 the run ended, 2 bad program files or environment (or the
// server refused the module), 3 the socket failed, 4 the board faulted (a
// reset, code outside the program, an overrun, a stall): the last line on
// stderr says which, where in the source, and when.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <string>

#include "chainsim_protocol.h"
#include "pic-module/gpsim_chip.h"
#include "pic-module/param_table.h"
#include "pic-module/pic_build.h"
#include "pic-module/pic_module.h"
#include "pic-module/server_link.h"

using namespace chainsim::pic;

namespace {

constexpr int kExitConfig = 2, kExitProtocol = 3, kExitFault = 4;

[[noreturn]] void die(int code, const std::string& msg) {
  std::fprintf(stderr, "chainsim pic: %s\n", msg.c_str());
  std::exit(code);
}

std::string env(const char* name, const char* fallback = nullptr) {
  const char* v = std::getenv(name);
  if (v && *v) return v;
  if (fallback) return fallback;
  die(kExitConfig, std::string(name) + " is not set: chainsim-pic is started by chainsim run for a module whose "
                                       "target is pic");
}

uint64_t env_number(const char* name, uint64_t fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* end = nullptr;
  const unsigned long long n = std::strtoull(v, &end, 10);
  if (*end != '\0') die(kExitConfig, std::string(name) + "=" + v + " is not a whole number");
  return n;
}

// gpsim prints its chatter on stdout ("not pwm mode. bug?" at every compare
// match): stdout goes nowhere, our own words go to stderr (the module's .out)
int silence_stdout() {
  std::fflush(stdout);
  const int kept = dup(1);
  const int null = open("/dev/null", O_WRONLY);
  if (null >= 0) {
    dup2(null, 1);
    close(null);
  }
  return kept;
}

void write_stats(const std::string& path, const PicModule& m) {
  if (path.empty()) return;
  std::ofstream out(path);
  out << m.stats().dump(1) << "\n";
}

int list_params(const std::string& hex, int out_fd) {
  try {
    const PicBuild b = load_pic_build(hex);
    GpsimChip chip(b.cod);
    std::string text = std::string(CS_PARAMS_HEADER) + "\n";
    const int64_t table = b.code_at("_hal_param_table");
    if (table >= 0) {
      for (const auto& p : read_param_table(static_cast<uint32_t>(table), [&](uint32_t a) { return chip.flash_byte(a); }))
        text += p.name + "\tint32\t" + std::to_string(p.min) + "\t" + std::to_string(p.max) + "\t" +
                std::to_string(p.def) + "\t(the board's build keeps no type or meaning)\n";
    }
    if (write(out_fd, text.data(), text.size()) != static_cast<ssize_t>(text.size())) return kExitConfig;
    return 0;
  } catch (const std::exception& e) {
    die(kExitConfig, e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int out_fd = silence_stdout();
  if (argc == 3 && std::strcmp(argv[1], CS_PARAMS_ARG) == 0) return list_params(argv[2], out_fd);
  if (argc != 2 || argv[1][0] == '-')
    die(kExitConfig, "usage: chainsim-pic PROGRAM.hex | chainsim-pic " CS_PARAMS_ARG " PROGRAM.hex");

  const std::string socket = env("CHAINSIM_SOCKET");
  const std::string type = env("CHAINSIM_MODULE_TYPE");
  const uint64_t index = env_number("CHAINSIM_MODULE_INDEX", UINT64_MAX);
  if (index > 0xFFFF) die(kExitConfig, "CHAINSIM_MODULE_INDEX is not set or not a module index");
  const std::string stats_path = env("CHAINSIM_PIC_STATS", "");
  PicOptions opt;
  opt.budget_us = env_number("CHAINSIM_PIC_CPU_BUDGET_US", 0);
  opt.stall_ms = env_number("CHAINSIM_PIC_STALL_MS", opt.stall_ms);
  const std::string overrun = env("CHAINSIM_PIC_ON_OVERRUN", "stop");
  if (overrun != "stop" && overrun != "warn") die(kExitConfig, "CHAINSIM_PIC_ON_OVERRUN=" + overrun + ": stop or warn");
  opt.overrun_warn = overrun == "warn";

  PicBuild build;
  std::unique_ptr<GpsimChip> chip;
  std::unique_ptr<PicModule> board;
  try {
    build = load_pic_build(argv[1]);
    chip = std::make_unique<GpsimChip>(build.cod);
    board = std::make_unique<PicModule>(chip.get(), &build, opt);
  } catch (const std::exception& e) {
    die(kExitConfig, e.what());
  }

  ServerLink link;
  cs_welcome w{};
  try {
    link.connect(socket);
    w = link.hello(static_cast<uint16_t>(index), type);
  } catch (const LinkError& e) {
    die(kExitProtocol, e.what());
  }
  try {
    std::map<std::string, int32_t> params;
    for (unsigned i = 0; i < w.n_params; ++i) params[w.params[i].name] = w.params[i].value;
    board->give_params(params);
  } catch (const std::exception& e) {
    die(kExitConfig, e.what());
  }

  cs_tick_begin tb{};
  cs_tick_end te{};
  double tick_cpu = 0, wait = 0;
  auto wall = [] {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
  };
  auto finish = [&] { board->host_times(tick_cpu, wait); };
  try {
    for (;;) {
      const double w0 = wall();
      if (!link.next_tick(&tb)) break;
      wait += wall() - w0;
      std::string fault;
      const double c0 = thread_cpu_s();
      try {
        fault = board->tick(tb, w.tick_us, &te);
      } catch (const std::runtime_error& e) {  // the build does not fit the module
        die(kExitConfig, e.what());
      }
      tick_cpu += thread_cpu_s() - c0;
      for (const auto& note : board->take_notes())
        std::fprintf(stderr, "chainsim pic: t=%.6f s: %s\n", static_cast<double>(tb.time_us) * 1e-6, note.c_str());
      link.send_tick_end(te);  // with a fault, the module's last words
      if (!fault.empty()) {
        finish();
        write_stats(stats_path, *board);
        die(kExitFault, fault);
      }
    }
  } catch (const LinkError& e) {
    finish();
    write_stats(stats_path, *board);
    die(kExitProtocol, e.what());
  }
  finish();
  write_stats(stats_path, *board);
  return 0;
}
