// A program's declared parameters, read from the program itself: hal-sim
// prints its hal_param_table when the program is started with
// CS_PARAMS_ARG (chainsim_protocol.h), before main runs. Why the program and
// not a file the build writes beside it: the declarations a run checks are
// those of the very binary it starts, a program built out of tree needs no
// build step of ours, and nothing can go stale (docs/firmware.md,
// "Parameters").
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cosim/endpoints.h"  // program_path: where a run finds a program
#include "scene/scene.h"
#include "scene/scene_params.h"

namespace chainsim {

// the listing's text -> declarations; throws std::runtime_error naming the
// first line that is not one
ProgramParams parse_params_listing(const std::string& text, const std::string& program);

// runs path with CS_PARAMS_ARG (at most 10 s of wall clock) and parses what
// it prints; throws std::runtime_error saying why there is no listing
// (`program` names it in messages)
// (args: more arguments after CS_PARAMS_ARG, e.g. the .hex for chainsim-pic)
ProgramParams read_program_params(const std::string& path, const std::string& program,
                                  const std::vector<std::string>& args = {});

// programs' listings by path, each program run once
class ProgramParamsCache {
 public:
  // the listing of the program at path; when there is none, on_error is
  // called with why and must throw the caller's error (if it returns, the
  // reason is thrown as std::runtime_error)
  const ProgramParams& get(const std::string& path, const std::string& program,
                           const std::function<void(const std::string& why)>& on_error,
                           const std::vector<std::string>& args = {});

 private:
  std::map<std::string, ProgramParams> by_path_;
};

// before a run starts anything: every endpoint's program exists and is
// executable, and every parameter the scene sets is one its program
// declares, within its range (each program that is given parameters is run
// once for its listing). A module whose target is pic: its PROGRAM.hex
// exists (its listing is read from the .hex's flash by chainsim-pic) and its
// module type's sensors fit the board's pins (model/pic_board.h). Throws
// SceneError at the scene's file:line:column.
void check_scene_programs(const Scene& scene, const std::string& firmware_dir);

}  // namespace chainsim
