// The chain compiled once. See chain_model.h.
#include "physics/chain_model.h"

#include "physics/module_builder.h"

namespace chainsim {

std::vector<std::string> ChainModel::types() const {
  std::vector<std::string> out;
  for (const ModuleDef& d : modules) out.push_back(d.type);
  return out;
}

const ModuleDef* ChainModel::first_of_type(const std::string& type) const {
  for (const ModuleDef& d : modules)
    if (d.type == type) return &d;
  return nullptr;
}

ChainModel compile_chain(const WorldConfig& config, const std::vector<std::string>& chain) {
  ChainModel c;
  c.modules.reserve(chain.size());
  for (const std::string& name : chain) {
    c.modules.push_back(find_module_def(config.module_types, name));
    validate_module_def(c.modules.back());
    // faces dock frame to frame: the chain advances by front -> back in module x
    const ModuleDef& def = c.modules.back();
    c.length_m += def.front.frame.position.x() - def.back.frame.position.x();
  }
  lay_chain(&c, config);
  return c;
}

void lay_chain(ChainModel* chain, const WorldConfig& cfg) {
  // head's front face at head_position, chain along +x rotated by heading
  // about z, or as head_orientation says
  Eigen::Isometry3d face = Eigen::Isometry3d::Identity();
  face.linear() = cfg.head_orientation
                      ? cfg.head_orientation->normalized().toRotationMatrix()
                      : Eigen::AngleAxisd(cfg.heading_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (cfg.roll_rad != 0)  // (only then: an unrolled chain's frame stays bit for bit what it was)
    face.linear() = face.linear() * Eigen::AngleAxisd(cfg.roll_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
  face.translation() = cfg.head_position;
  chain->frames.clear();
  for (const ModuleDef& def : chain->modules) {
    chain->frames.push_back(face * to_isometry(def.front.frame).inverse());
    face = chain->frames.back() * to_isometry(def.back.frame);
  }
}

}  // namespace chainsim
