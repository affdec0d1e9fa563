#include "chainsim/params_command.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "chainsim_protocol.h"
#include "cosim/program_params.h"
#include "cosim/run_options.h"

namespace chainsim {
namespace {

struct ParamsArgs {
  std::string program;
  std::string firmware_dir;
  bool markdown = false;
};

ParamsArgs g_params_args;

std::string range_text(const ParamDecl& d) { return std::to_string(d.min) + ".." + std::to_string(d.max); }

void print_table(const ProgramParams& p) {
  size_t w_name = 9, w_type = 4, w_range = 5;
  for (const ParamDecl& d : p.params) {
    w_name = std::max(w_name, d.name.size());
    w_type = std::max(w_type, d.type.size());
    w_range = std::max(w_range, range_text(d).size());
  }
  std::printf("%-*s  %-*s  %-*s  %8s  %s\n", static_cast<int>(w_name), "parameter", static_cast<int>(w_type), "type",
              static_cast<int>(w_range), "range", "default", "meaning");
  for (const ParamDecl& d : p.params)
    std::printf("%-*s  %-*s  %-*s  %8d  %s\n", static_cast<int>(w_name), d.name.c_str(), static_cast<int>(w_type),
                d.type.c_str(), static_cast<int>(w_range), range_text(d).c_str(), d.def, d.meaning.c_str());
}

// the form docs/firmware.md holds (a test compares the two)
void print_markdown(const ProgramParams& p) {
  std::printf("| parameter | type | range | default | meaning |\n|---|---|---|---|---|\n");
  for (const ParamDecl& d : p.params)
    std::printf("| `%s` | %s | %s | %d | %s |\n", d.name.c_str(), d.type.c_str(), range_text(d).c_str(), d.def,
                d.meaning.c_str());
}

int run_params() {
  const std::string path = program_path(g_params_args.program, g_params_args.firmware_dir);
  ProgramParams p;
  try {
    p = read_program_params(path, g_params_args.program);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s: no parameter listing: %s\n", path.c_str(), e.what());
    return kExitBadInput;
  }
  if (g_params_args.markdown) {
    print_markdown(p);
  } else {
    std::printf("%s (%s): %zu parameter%s\n", g_params_args.program.c_str(), path.c_str(), p.params.size(),
                p.params.size() == 1 ? "" : "s");
    if (!p.params.empty()) print_table(p);
  }
  return std::fflush(stdout) == 0 ? kExitOk : kExitInternal;
}

}  // namespace

Command add_params_command(CLI::App& app) {
  auto* sub = app.add_subcommand("params", "list the parameters a module program declares: name, type, range, "
                                           "default, meaning (what a scene's params may set)");
  sub->add_option("program", g_params_args.program, "program name (e.g. fw-central) or path")->required();
  sub->add_option("--firmware-dir", g_params_args.firmware_dir,
                  "where to look for the program first (DIR[:DIR...]), then next to chainsim");
  sub->add_flag("--markdown", g_params_args.markdown, "a Markdown table, as in docs/firmware.md");
  sub->footer("The program is run with " CS_PARAMS_ARG " (hal-sim prints its hal_param_table and exits). "
              "Exit codes: 0 listed; 1 the program is missing or printed no listing.");
  return {sub, [] { return run_params(); }};
}


}  // namespace chainsim
