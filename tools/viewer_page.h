// The viewer page: one self-contained HTML file with the viewer bundle
// (share/chainsim/viewer.js and viewer.css, built by the CMake target
// chainsim_viewer_bundle) and the data it shows inlined. Used by
// `chainsim view` (a replay of a run directory) and `chainsim run --live`.
#pragma once

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace chainsim {

struct ViewerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// where the bundle is: $CHAINSIM_VIEWER_DIR, else <exe dir>/../share/chainsim
std::string viewer_assets_dir();

// the page; boot is what the page starts from:
//   {"mode":"replay","scene":{...},"trace":"<csv>","bus":"<log>","summary":{...}}
//   {"mode":"live"}
// Throws ViewerError when the bundle is missing.
std::string viewer_page(const nlohmann::json& boot, const std::string& title);

// the boot data of a run directory (scene.json, trace.csv, bus.log, summary.json);
// throws ViewerError naming what is missing
nlohmann::json replay_boot(const std::string& run_dir);

}  // namespace chainsim
