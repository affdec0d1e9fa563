// Program parameters as the programs declare them (hal/hal_param.h: each
// program's hal_param_table, which hal-sim lists when the program is run
// with --chainsim-params), and the check of a scene's parameters against
// them: a name the program does not declare or a value outside its range is
// a SceneError at the key's file:line:column, naming the endpoint and the
// program. Getting the declarations (running the program) is
// cosim/program_params.h; this file only compares.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace chainsim {

// one declared parameter
struct ParamDecl {
  std::string name;
  std::string type;  // "uint8", "int16", "uint16", "int32", "uint32"
  int32_t min = 0, max = 0, def = 0;
  std::string meaning;
};

// the declarations of one program
struct ProgramParams {
  std::string program;  // as the scene names it, for messages
  std::vector<ParamDecl> params;
  const ParamDecl* find(const std::string& name) const;
  // "gait, amplitude_cdeg, ..." in declaration order
  std::string names() const;
};

// the declarations of the program of endpoint `who` (a SceneModule of the
// scene: a module or the central control); throws SceneError when they
// cannot be had (the program is missing, or does not list them)
using ParamsOf = std::function<const ProgramParams&(const SceneModule& endpoint, const std::string& who)>;

// "module 3 (rotation)" or "the central control"
std::string scene_endpoint_name(const Scene& scene, int index);

// every parameter of every endpoint that sets any, against its program's
// declarations (params_of is called only for those); throws SceneError
void check_scene_params(const Scene& scene, const ParamsOf& params_of);

// the declared parameter nearest to a misspelled name (edit distance at most
// 2, or one a prefix of the other), or "" when none is near
std::string nearest_param(const ProgramParams& decls, const std::string& name);

}  // namespace chainsim
