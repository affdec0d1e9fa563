#include "scene/scene_stop.h"

#include <cstdio>

#include "scene/scene_yaml.h"
#include "text/number_text.h"

namespace chainsim {

namespace {

std::string along_text(const StopRule& r) {
  if (r.along_pipe) return "pipe";
  if (r.axis == Eigen::Vector3d::UnitX()) return "x";
  if (r.axis == Eigen::Vector3d::UnitY()) return "y";
  if (r.axis == Eigen::Vector3d::UnitZ()) return "z";
  return "[" + general_text(r.axis.x()) + ", " + general_text(r.axis.y()) + ", " + general_text(r.axis.z()) + "]";
}

}  // namespace

std::string stop_rule_text(const StopRule& r) {
  const std::string what = std::string(r.tail ? "tail" : "head") + " along " + along_text(r);
  if (r.kind == StopRule::Kind::NoProgress)
    return "no_progress of " + what + " by " + general_text(r.by_m) + " m within " + general_text(r.within_s) + " s";
  return "not_reached: " + what + " to " + general_text(r.reach_m) + " m by " + general_text(r.by_s) + " s";
}

YAML::Node stop_rule_yaml(const StopRule& r) {
  const auto number = [](double v) { return YAML::Node(round_trip_text(v)); };
  YAML::Node n;
  n["of"] = r.tail ? "tail" : "head";
  const std::string a = along_text(r);
  if (r.along_pipe || (a.size() == 1 && !r.along_given)) {
    n["along"] = r.along_pipe ? "pipe" : a;
  } else {  // a vector: as written, which reading normalises again
    YAML::Node v(YAML::NodeType::Sequence);
    const Eigen::Vector3d along = r.along_given.value_or(r.axis);
    for (int i = 0; i < 3; ++i) v.push_back(number(along[i]));
    v.SetStyle(YAML::EmitterStyle::Flow);
    n["along"] = v;
  }
  YAML::Node e;
  if (r.kind == StopRule::Kind::NoProgress) {
    n["by_m"] = number(r.by_m);
    n["within_s"] = number(r.within_s);
    e["no_progress"] = n;
  } else {
    n["reach_m"] = number(r.reach_m);
    n["by_s"] = number(r.by_s);
    e["not_reached"] = n;
  }
  return e;
}

void load_scene_stop_when(const std::string& file, const YAML::Node& list, Scene* scene, const std::string& path) {
  if (!list) return;
  const SceneYaml y{file};
  if (!list.IsSequence())
    y.fail(list, "'" + path + "' must be a list of {no_progress: {...}} or {not_reached: {...}}");
  const bool has_pipe = scene->world.environment.type == EnvironmentType::Pipe;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string p = path + "[" + std::to_string(i) + "]";
    const YAML::Node e = list[i];
    if (!e.IsMap() || e.size() != 1)
      y.fail(e, "'" + p + "' must be a mapping of one key: no_progress or not_reached");
    y.keys(e, p, {"no_progress", "not_reached"});
    StopRule r;
    const bool np = static_cast<bool>(e["no_progress"]);
    const std::string q = p + "." + (np ? "no_progress" : "not_reached");
    const YAML::Node n = np ? e["no_progress"] : e["not_reached"];
    if (!n.IsMap()) y.fail(n, "'" + q + "' must be a mapping");
    if (np) {
      y.keys(n, q, {"of", "along", "by_m", "within_s"});
      r.kind = StopRule::Kind::NoProgress;
      for (const char* k : {"by_m", "within_s"})
        if (!n[k]) y.fail(n, "'" + q + "' needs '" + k + "'");
      r.by_m = y.positive(n, "by_m", 0, 1000, q);
      r.within_s = y.positive(n, "within_s", 0, 86400, q);
    } else {
      y.keys(n, q, {"of", "along", "reach_m", "by_s"});
      r.kind = StopRule::Kind::NotReached;
      for (const char* k : {"reach_m", "by_s"})
        if (!n[k]) y.fail(n, "'" + q + "' needs '" + k + "'");
      r.reach_m = y.number(n, "reach_m", 0, -1e6, 1e6, q);
      r.by_s = y.number(n, "by_s", 0, 0, 86400, q);
    }
    r.tail = y.choice(n, "of", "head", {"head", "tail"}, q) == "tail";
    const YAML::Node a = n["along"];
    if (a && a.IsSequence()) {
      r.axis = y.vec3(n, "along", r.axis, q, 1e6);
      if (r.axis.norm() < 1e-12) y.fail(a, "'" + q + ".along' must not be the zero vector");
      r.along_given = r.axis;
      r.axis.normalize();
    } else {
      const std::string along = y.choice(n, "along", "x", {"x", "y", "z", "pipe"}, q);
      r.along_pipe = along == "pipe";
      r.axis = along == "y" ? Eigen::Vector3d::UnitY() : along == "z" ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
      if (r.along_pipe && !has_pipe) y.fail(a, "'" + q + ".along' is pipe but the environment is not a pipe");
    }
    scene->stop_when.push_back(r);
  }
}

}  // namespace chainsim
