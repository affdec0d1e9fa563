// The chain compiled once: each module's definition, looked up by type name
// (the scene's own types first, then the built-ins) and validated, its module
// frame as the chain is laid from the head pose, and the chain's length.
// Everything that needs a module's definition reads it here (the World,
// placement, the trace's sensor columns, scene.json), so a type name is
// resolved in one place: compile_chain. The flow: scene -> chain model ->
// world -> outputs (docs/architecture.md).
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "model/module_def.h"
#include "physics/world_config.h"

namespace chainsim {

struct ChainModel {
  std::vector<ModuleDef> modules;          // head first
  // each module's frame -> world, laid head first from the config's head pose
  // (head_position, heading_rad, roll_rad or head_orientation): module k's
  // back face on module k + 1's front face
  std::vector<Eigen::Isometry3d> frames;
  double length_m = 0;                     // head's front face to tail's back face, straight

  int size() const { return static_cast<int>(modules.size()); }
  std::vector<std::string> types() const;
  // the definition of the chain's first module of that type; nullptr when
  // the chain has none
  const ModuleDef* first_of_type(const std::string& type) const;
};

// chain: module type names, head first; each looked up in config.module_types,
// then the built-ins, and laid from config's head pose. Throws
// std::invalid_argument naming an unknown type or a bad definition.
ChainModel compile_chain(const WorldConfig& config, const std::vector<std::string>& chain);

// lays chain's frames again from config's head pose (after placement has set it)
void lay_chain(ChainModel* chain, const WorldConfig& config);

}  // namespace chainsim
