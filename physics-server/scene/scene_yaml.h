// Strict reading of scene YAML shared by the scene loaders (scene.cpp,
// scene_environment.cpp, scene_modules.cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>

#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "environment/material.h"
#include "scene/scene.h"

namespace chainsim {

// reads scene YAML for one file: every error is a SceneError that starts
// with file:line:column and names the key
struct SceneYaml {
  const std::string& file;

  // "file:line:column" of node n (just "file" when it has no position)
  std::string where(const YAML::Node& n) const {
    std::ostringstream s;
    s << file;
    const YAML::Mark m = n.Mark();
    if (m.line >= 0) s << ":" << (m.line + 1) << ":" << (m.column + 1);
    return s.str();
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const {
    throw SceneError(where(n) + ": " + what);
  }
  void keys(const YAML::Node& map, const std::string& path, const std::set<std::string>& allowed) const {
    if (!map.IsMap()) fail(map, "'" + path + "' must be a mapping");
    for (const auto& kv : map) {
      const std::string key = kv.first.as<std::string>();
      if (allowed.count(key)) continue;
      std::string known;
      for (const auto& a : allowed) known += (known.empty() ? "" : ", ") + a;
      fail(kv.first, "unknown key '" + key + "' in '" + path + "' (known: " + known + ")");
    }
  }
  // a number in [lo, hi]; lo_open: > lo
  double number(const YAML::Node& map, const std::string& key, double dflt, double lo, double hi,
                const std::string& path, bool lo_open = false) const {
    const YAML::Node n = map[key];
    if (!n) return dflt;
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, "'" + path + "." + key + "' must be a number");
    }
    std::ostringstream s;
    s << "'" << path << "." << key << "' = " << v;
    if (lo_open && lo == 0 && !(v > 0)) fail(n, s.str() + " must be > 0");
    if (!std::isfinite(v) || v < lo || v > hi || (lo_open && v <= lo)) {
      s << " is out of range " << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
      fail(n, s.str());
    }
    return v;
  }
  double positive(const YAML::Node& map, const std::string& key, double dflt, double hi,
                  const std::string& path) const {
    return number(map, key, dflt, 0.0, hi, path, true);
  }
  std::string text(const YAML::Node& map, const std::string& key, const std::string& dflt,
                   const std::string& path) const {
    const YAML::Node n = map[key];
    if (!n) return dflt;
    if (!n.IsScalar() || n.as<std::string>().empty())
      fail(n, "'" + path + "." + key + "' must be a non-empty string");
    return n.as<std::string>();
  }
  bool flag(const YAML::Node& map, const std::string& key, bool dflt, const std::string& path) const {
    const YAML::Node n = map[key];
    if (!n) return dflt;
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(n, "'" + path + "." + key + "' must be true or false");
    }
  }
  Eigen::Vector3d vec3(const YAML::Node& map, const std::string& key, const Eigen::Vector3d& dflt,
                       const std::string& path) const {
    const YAML::Node n = map[key];
    if (!n) return dflt;
    const std::string msg = "'" + path + "." + key + "' must be a list of 3 numbers [x, y, z]";
    if (!n.IsSequence() || n.size() != 3) fail(n, msg);
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      try {
        v[i] = n[i].as<double>();
      } catch (const YAML::Exception&) {
        fail(n[i], msg);
      }
      if (!std::isfinite(v[i])) fail(n[i], msg);
    }
    return v;
  }
  // one of choices
  std::string choice(const YAML::Node& map, const std::string& key, const std::string& dflt,
                     const std::vector<std::string>& choices, const std::string& path) const {
    const std::string v = text(map, key, dflt, path);
    std::string known;
    for (const auto& c : choices) {
      if (c == v) return v;
      known += (known.empty() ? "" : ", ") + c;
    }
    fail(map[key], "'" + path + "." + key + "' '" + v + "' is not known (known: " + known + ")");
  }
  Material material(const YAML::Node& n, const std::string& path, const Material& dflt,
                    bool allow_between = false) const {
    if (allow_between)
      keys(n, path, {"between", "mu", "bounce", "soft_erp", "soft_cfm"});
    else
      keys(n, path, {"mu", "bounce", "soft_erp", "soft_cfm"});
    Material m = dflt;
    m.mu = number(n, "mu", m.mu, 0.0, 100.0, path);
    m.bounce = number(n, "bounce", m.bounce, 0.0, 1.0, path);
    m.soft_erp = number(n, "soft_erp", m.soft_erp, 0.0, 1.0, path);
    m.soft_cfm = number(n, "soft_cfm", m.soft_cfm, 0.0, 1.0, path);
    return m;
  }
};

}  // namespace chainsim
