// `chainsim view RUN_DIR`: writes RUN_DIR/replay.html, a self-contained page
// (opens from disk) that replays the run; with --png TIME it renders a picture
// of the scene at that time with headless Chromium instead.
#pragma once

#include "chainsim/command.h"

#include <string>

namespace chainsim {

struct ViewArgs {
  std::string run_dir;
  std::string other_dir;    // a second run: the page compares the two (compare.html)
  std::string out;          // replay.html path (default RUN_DIR/replay.html) or the PNG
  double png_time = -1;     // >= 0: render a PNG of this time
  std::string size = "960x540";
  std::string hash;         // more page options for the picture, e.g. "follow=0"
};

int cmd_view(const ViewArgs& a);

// registers the `view` subcommand on app: what runs it, returning its exit code
Command add_view_command(CLI::App& app);

// the Chromium program: $CHAINSIM_CHROMIUM, else /usr/bin/chromium; empty when missing
std::string find_chromium();

}  // namespace chainsim
