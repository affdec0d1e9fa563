// The viewer page: one self-contained HTML file with the viewer bundle
// (share/chainsim/viewer.js and viewer.css, built by the CMake target
// chainsim_viewer_bundle) and the data it shows inlined. Used by
// `chainsim view` (a replay of a run directory) and `chainsim run --live`.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

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

// the boot data of a run directory (scene.json, trace.csv, bus.log, summary.json,
// and "mesh_files": environment_files() of the scene); throws ViewerError naming
// what is missing. A mesh file that is not there is not an error: `warnings`
// (when given) gets a line naming it, and the page says it is not drawn.
nlohmann::json replay_boot(const std::string& run_dir, std::vector<std::string>* warnings = nullptr);

// the mesh files of a scene.json's environment (type "mesh", also inside
// "group" parts), for the page to parse with three.js's loaders:
//   {"<mesh.file as in scene.json>": {"base64": "...", "bytes": N,
//                                     "extra": {"<uri>": "<base64>", ...}}}
// ("extra": the external buffers and images a .gltf refers to). A file is
// looked for at mesh.file, then at mesh.file_as_given relative to the scene
// file's directory (scene.json "source") and to run_dir; one that is not found
// gets {"error": "..."} and a line in warnings.
nlohmann::json environment_files(const nlohmann::json& scene, const std::string& run_dir,
                                 std::vector<std::string>* warnings);

}  // namespace chainsim
