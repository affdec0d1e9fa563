// Contact parameters between two surfaces. Surfaces have names: every module
// body is "module"; environment parts name theirs (environment.h). A contact
// uses the parameters of its pair of surface names.
#pragma once

#include <string>

namespace chainsim {

// contact parameters of a pair of surfaces
struct Material {
  double mu = 0.8;          // Coulomb friction coefficient
  double bounce = 0.0;      // restitution, 0..1
  double soft_erp = 0.2;    // contact error reduction
  double soft_cfm = 1e-5;   // contact constraint force mixing
};

// one row of the pair table: contacts between surfaces a and b (either order)
struct MaterialPair {
  std::string a, b;
  Material material;
};

// name of the surface of every module body
inline const char* module_surface_name() { return "module"; }

}  // namespace chainsim
