#include "chainsim/robot_calibration.h"


#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>
#include <nlopt.hpp>

#include <fcntl.h>
#include <sys/wait.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/module_file.h"

extern char** environ;

namespace chainsim {
namespace robotcal {
namespace {

// a measured table: key (text put in place of {slope}), real speed, optional
// paper-simulator speed, in cm/s
struct Row {
  std::string key;
  double real = 0, paper = NAN;
};

std::string rtrim(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.pop_back();
  size_t a = 0;
  while (a < s.size() && (s[a] == ' ' || s[a] == '\t')) ++a;
  return s.substr(a);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream is(line);
  while (std::getline(is, cell, ',')) out.push_back(rtrim(cell));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

// columns: the first is the key (slope_deg or any name), `real_speed_cm_s`
// (required), `paper_sim_speed_cm_s` (optional); '#' lines are comments
std::vector<Row> read_table(const std::string& path, std::string* key_name) {
  std::ifstream f(path);
  if (!f) throw RobotError(path + ": cannot read");
  std::string line;
  int ln = 0, c_real = -1, c_paper = -1;
  std::vector<std::string> header;
  std::vector<Row> rows;
  while (std::getline(f, line)) {
    ++ln;
    const std::string t = rtrim(line);
    if (t.empty() || t[0] == '#') continue;
    auto cells = split_csv(t);
    if (header.empty()) {
      header = cells;
      for (size_t i = 0; i < cells.size(); ++i) {
        if (cells[i] == "real_speed_cm_s") c_real = int(i);
        if (cells[i] == "paper_sim_speed_cm_s") c_paper = int(i);
      }
      if (c_real <= 0)
        throw RobotError(path + ":" + std::to_string(ln) +
                         ": the header needs a key column first and a column real_speed_cm_s");
      *key_name = cells[0];
      continue;
    }
    if (cells.size() != header.size())
      throw RobotError(path + ":" + std::to_string(ln) + ": " + std::to_string(cells.size()) + " cells, the header has " +
                       std::to_string(header.size()));
    Row r;
    r.key = cells[0];
    auto num = [&](int c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (cells[c].empty() || *end || !std::isfinite(v))
        throw RobotError(path + ":" + std::to_string(ln) + ":" + std::to_string(c + 1) + ": '" + cells[c] +
                         "' is not a number");
      return v;
    };
    if (r.key.empty()) throw RobotError(path + ":" + std::to_string(ln) + ":1: empty key");
    r.real = num(c_real);
    if (c_paper >= 0 && !cells[c_paper].empty()) r.paper = num(c_paper);
    rows.push_back(r);
  }
  if (rows.size() < 2) throw RobotError(path + ": at least 2 rows are needed");
  return rows;
}

// ---------------------------------------------------------------- catalogue

// a knob: one robot-level parameter, searched as a factor of its nominal
// value in [lo, hi] on a log scale
struct Knob {
  const char* name;     // report name
  const char* param;    // what it sets
  const char* module;   // module type it needs in the chain ("" = any scene)
  const char* meaning;
  double lo, hi;
};

const std::vector<Knob>& knobs() {
  static const std::vector<Knob> k = {
      {"drive_stall", "stall_torque_nm (dc_motor) or fmax_n (screw_drive)", "helicoidal",
       "the helicoidal drive's stall torque or thrust (force-speed line)", 0.5, 2.0},
      {"drive_free_speed", "free_speed_rad_s (dc_motor) or v_free_m_s (screw_drive)", "helicoidal",
       "the helicoidal drive's no-load speed", 0.7, 1.4},
      {"wheel_preload", "preload_n (every wheel set)", "helicoidal",
       "the wheels' spring force on the wall (their grip and centring)", 0.25, 4.0},
      {"wheel_friction", "mu (every wheel set)", "helicoidal",
       "the tyres' friction across the wheel (how much thrust each wheel grips)", 0.3, 2.0},
      {"arm_grip_torque", "kt (all support arm servos)", "support",
       "the support arms' servo torque constant: how hard the arms press the wall (slip of the grip)", 0.1, 1.5},
      {"pad_friction", "mu (every pad)", "support", "the support arms' pads' friction on the wall", 0.2, 2.0},
      {"wall_friction", "environment.material.mu", "", "module-pipe Coulomb friction", 0.2, 5.0},
  };
  return k;
}

struct Scenes {
  std::vector<std::string> texts;  // template per row, {slope} filled
  std::vector<std::string> dirs;   // each scene's directory (for relative paths)
  std::map<std::string, std::string> type_text;  // module type -> its definition text
  std::map<std::string, double> nominal;          // knob -> nominal value
  std::vector<int> usable;                        // knob indices that apply
};

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw RobotError(path + ": cannot read");
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string replace_all(std::string s, const std::string& a, const std::string& b) {
  for (size_t p = s.find(a); p != std::string::npos; p = s.find(a, p + b.size())) s.replace(p, a.size(), b);
  return s;
}

std::vector<std::string> chain_types(const YAML::Node& root) {
  std::vector<std::string> t;
  const YAML::Node c = root["chain"];
  static const std::map<char, std::string> letters = {{'T', "touch"},     {'R', "rotation"}, {'H', "helicoidal"},
                                                      {'S', "support"},   {'E', "extension"}, {'W', "traveller"},
                                                      {'P', "passive"}};
  if (c && c.IsScalar()) {
    for (char ch : c.as<std::string>())
      if (letters.count(ch)) t.push_back(letters.at(ch));
  } else if (c && c.IsSequence()) {
    for (const auto& m : c)
      if (m["type"]) t.push_back(m["type"].as<std::string>());
  }
  return t;
}

Scenes load_scenes(const std::string& tmpl, const std::vector<Row>& rows) {
  Scenes s;
  for (const auto& r : rows) {
    const std::string path = replace_all(tmpl, "{slope}", r.key);
    if (!std::filesystem::exists(path))
      throw RobotError(path + ": no such scene (template " + tmpl + ", row " + r.key + ")");
    s.texts.push_back(read_text(path));
    s.dirs.push_back(std::filesystem::absolute(path).parent_path().string());
  }
  YAML::Node root;
  try {
    root = YAML::Load(s.texts[0]);
  } catch (const YAML::Exception& e) {
    throw RobotError(replace_all(tmpl, "{slope}", rows[0].key) + ": " + e.what());
  }
  const auto types = chain_types(root);
  for (const auto& type : types) {
    if (s.type_text.count(type)) continue;
    if (root["module_types"] && root["module_types"][type]) {
      std::filesystem::path p = root["module_types"][type].as<std::string>();
      if (p.is_relative()) p = std::filesystem::path(s.dirs[0]) / p;
      s.type_text[type] = read_text(p.string());
    } else {
      for (const auto& b : builtin_module_files())
        if (type == b.name) s.type_text[type] = b.text;
    }
  }
  double mu = 0.8;
  if (root["environment"] && root["environment"]["material"] && root["environment"]["material"]["mu"])
    mu = root["environment"]["material"]["mu"].as<double>();
  s.nominal["wall_friction"] = mu;
  if (s.type_text.count("helicoidal")) {
    YAML::Node d = YAML::Load(s.type_text["helicoidal"]);
    for (const auto& a : d["actuators"]) {
      const std::string t = a["type"] ? a["type"].as<std::string>() : "";
      const bool motor = t == "dc_motor";
      if (t != "screw_drive" && !motor) continue;
      const char* stall = motor ? "stall_torque_nm" : "fmax_n";
      const char* free = motor ? "free_speed_rad_s" : "v_free_m_s";
      s.nominal["drive_stall"] = a[stall] ? a[stall].as<double>() : 0;
      s.nominal["drive_free_speed"] = a[free] ? a[free].as<double>() : 0;
      break;
    }
    // wheel knobs scale every set's own value; nominal = the first set's
    if (d["wheels"] && d["wheels"].IsSequence() && d["wheels"].size() > 0) {
      const YAML::Node w = d["wheels"][0];
      s.nominal["wheel_preload"] = w["preload_n"] ? w["preload_n"].as<double>() : 0;
      s.nominal["wheel_friction"] = w["mu"] ? w["mu"].as<double>() : 0;
    }
  }
  if (s.type_text.count("support")) {
    s.nominal["arm_grip_torque"] = 0.14;  // servo_model.h default kt, N m/A
    YAML::Node d = YAML::Load(s.type_text["support"]);
    if (d["pads"] && d["pads"].IsSequence() && d["pads"].size() > 0 && d["pads"][0]["mu"])
      s.nominal["pad_friction"] = d["pads"][0]["mu"].as<double>();
  }
  for (size_t k = 0; k < knobs().size(); ++k) {
    const std::string m = knobs()[k].module;
    if (!m.empty() && !s.type_text.count(m)) continue;
    if (s.nominal.count(knobs()[k].name) && s.nominal[knobs()[k].name] > 0) s.usable.push_back(int(k));
  }
  return s;
}

using Setting = std::map<int, double>;  // knob -> factor of nominal

std::string setting_key(const Setting& st) {
  std::ostringstream s;
  for (const auto& [k, v] : st) s << k << "=" << std::llround(v * 1e6) << ";";
  return s.str();
}

// the scene text for row i with the knobs set; module type files go to dir
std::string make_scene(const Scenes& sc, size_t i, const Setting& st, const std::string& dir) {
  YAML::Node root = YAML::Load(sc.texts[i]);
  // make relative paths of the template absolute: the scene is written elsewhere
  if (root["module_types"])
    for (auto kv : root["module_types"]) {
      std::filesystem::path p = kv.second.as<std::string>();
      if (p.is_relative()) root["module_types"][kv.first.as<std::string>()] = (std::filesystem::path(sc.dirs[i]) / p).string();
    }
  if (root["environment"] && root["environment"]["mesh"] && root["environment"]["mesh"]["file"]) {
    std::filesystem::path p = root["environment"]["mesh"]["file"].as<std::string>();
    if (p.is_relative()) root["environment"]["mesh"]["file"] = (std::filesystem::path(sc.dirs[i]) / p).string();
  }
  std::string tag;
  for (const auto& [k, f] : st) {
    const std::string name = knobs()[k].name;
    const double v = f * sc.nominal.at(name);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%.6g", tag.empty() ? "" : "_", v);
    tag += std::string(name) + buf;
    if (name == "wall_friction") {
      root["environment"]["material"]["mu"] = v;
    } else if (name == "drive_stall" || name == "drive_free_speed") {
      // edited below, together
    }
  }
  auto factor = [&](const char* name) {
    for (const auto& [k, f] : st)
      if (std::string(knobs()[k].name) == name) return f;
    return 1.0;
  };
  const double ft = factor("drive_stall"), fv = factor("drive_free_speed"), fg = factor("arm_grip_torque");
  const double fp = factor("wheel_preload"), fm = factor("wheel_friction"), fpad = factor("pad_friction");
  std::hash<std::string> h;
  if ((ft != 1.0 || fv != 1.0 || fp != 1.0 || fm != 1.0) && sc.type_text.count("helicoidal")) {
    YAML::Node d = YAML::Load(sc.type_text.at("helicoidal"));
    for (auto a : d["actuators"]) {
      const std::string t = a["type"] ? a["type"].as<std::string>() : "";
      if (t != "screw_drive" && t != "dc_motor") continue;
      a[t == "dc_motor" ? "stall_torque_nm" : "fmax_n"] = ft * sc.nominal.at("drive_stall");
      a[t == "dc_motor" ? "free_speed_rad_s" : "v_free_m_s"] = fv * sc.nominal.at("drive_free_speed");
    }
    if (d["wheels"])
      for (auto w : d["wheels"]) {
        if (w["preload_n"]) w["preload_n"] = fp * w["preload_n"].as<double>();
        if (w["mu"]) w["mu"] = fm * w["mu"].as<double>();
      }
    YAML::Emitter e;
    e << d;
    const std::string file = dir + "/helicoidal-" + std::to_string(h(setting_key(st))) + ".yaml";
    std::ofstream(file) << e.c_str() << "\n";
    root["module_types"]["helicoidal"] = file;
  }
  if ((fg != 1.0 || fpad != 1.0) && sc.type_text.count("support")) {
    YAML::Node d = YAML::Load(sc.type_text.at("support"));
    if (d["pads"])
      for (auto p : d["pads"])
        if (p["mu"]) p["mu"] = fpad * p["mu"].as<double>();
    for (auto a : d["actuators"])
      if (a["type"] && a["type"].as<std::string>() == "servo") {
        const double kt = a["servo"] && a["servo"]["kt"] ? a["servo"]["kt"].as<double>() : 0.14;
        a["servo"]["kt"] = fg * kt;
      }
    YAML::Emitter e;
    e << d;
    const std::string file = dir + "/support-" + std::to_string(h(setting_key(st))) + ".yaml";
    std::ofstream(file) << e.c_str() << "\n";
    root["module_types"]["support"] = file;
  }
  YAML::Emitter e;
  e << root;
  return e.c_str();
}

// the unit vector of the pipe's first straight segment (default: the run's
// own displacement direction)
bool pipe_axis(const std::string& text, double u[3]) {
  YAML::Node root = YAML::Load(text);
  const YAML::Node p = root["environment"] ? root["environment"]["pipe"] : YAML::Node();
  if (!p || !p["segments"] || !p["segments"].IsSequence() || p["segments"].size() == 0) return false;
  const YAML::Node s0 = p["segments"][0];
  if (s0["type"] && s0["type"].as<std::string>() != "straight") return false;
  const double deg = M_PI / 180;
  const double slope = (s0["slope_deg"] ? s0["slope_deg"].as<double>() : p["slope_deg"] ? p["slope_deg"].as<double>() : 0) * deg;
  const double head = (p["heading_deg"] ? p["heading_deg"].as<double>() : 0) * deg;
  u[0] = std::cos(slope) * std::cos(head), u[1] = std::cos(slope) * std::sin(head), u[2] = std::sin(slope);
  return true;
}

// speed of the head module's first body along u between t0 and the end, cm/s
double trace_speed(const std::string& trace, double t0, const double* u) {
  std::ifstream f(trace);
  if (!f) throw RobotError(trace + ": cannot read");
  std::string line;
  std::getline(f, line);
  const auto head = split_csv(line);
  if (head.size() < 4 || head[1].substr(0, 3) != "m0." || head[1].back() != 'x')
    throw RobotError(trace + ": no head position columns");
  double ta = NAN, tb = NAN, pa[3] = {0, 0, 0}, pb[3] = {0, 0, 0};
  while (std::getline(f, line)) {
    const auto c = split_csv(line);
    if (c.size() < 4) continue;
    const double t = std::atof(c[0].c_str());
    if (t + 1e-9 < t0) continue;
    double p[3] = {std::atof(c[1].c_str()), std::atof(c[2].c_str()), std::atof(c[3].c_str())};
    if (std::isnan(ta)) ta = t, std::copy(p, p + 3, pa);
    tb = t, std::copy(p, p + 3, pb);
  }
  if (std::isnan(ta) || !(tb > ta)) throw RobotError(trace + ": the run is shorter than the speed window");
  double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]}, dir[3];
  if (u) std::copy(u, u + 3, dir);
  else {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; ++i) dir[i] = n > 0 ? d[i] / n : 0;
  }
  return 100 * (d[0] * dir[0] + d[1] * dir[1] + d[2] * dir[2]) / (tb - ta);
}

std::string self_exe() {
  std::error_code ec;
  auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw RobotError("cannot find the chainsim executable (/proc/self/exe)");
  return p.string();
}

// one `chainsim run` process; returns its exit code
int spawn_run(const std::string& exe, const std::string& scene, const std::string& out, double duration,
                     const std::string& fwdir, const std::string& log) {
  std::vector<std::string> args = {exe, "run", scene, "--out", out, "--duration", std::to_string(duration), "--quiet"};
  if (!fwdir.empty()) args.insert(args.end(), {"--firmware-dir", fwdir});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  pid_t pid;
  const int rc = posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return 127;
  int st = 0;
  while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

struct Runner {
  const RobotArgs* a;
  const Scenes* sc;
  std::vector<Row> rows;
  std::string exe, work;
  std::map<std::string, std::vector<double>> cache;  // setting -> speeds per row
  int runs = 0;
  double run_wall = 0;

  std::vector<double> speeds(const Setting& st) {
    const std::string key = setting_key(st);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    const std::string dir = work + "/e" + std::to_string(cache.size());
    std::filesystem::create_directories(dir);
    std::vector<double> v(rows.size(), NAN);
    std::vector<std::string> scenes(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      scenes[i] = dir + "/scene-" + rows[i].key + ".yaml";
      std::ofstream(scenes[i]) << make_scene(*sc, i, st, dir);
    }
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t i0 = 0; i0 < rows.size(); i0 += size_t(std::max(1, a->jobs))) {
      std::vector<std::future<int>> fs;
      const size_t i1 = std::min(rows.size(), i0 + size_t(std::max(1, a->jobs)));
      for (size_t i = i0; i < i1; ++i)
        fs.push_back(std::async(std::launch::async, [&, i] {
          return spawn_run(exe, scenes[i], dir + "/run-" + rows[i].key, a->duration_s, a->firmware_dir,
                           dir + "/run-" + rows[i].key + ".log");
        }));
      for (size_t i = i0; i < i1; ++i) {
        const int rc = fs[i - i0].get();
        ++runs;
        if (rc != 0)
          throw RobotError("chainsim run " + scenes[i] + " failed with exit code " + std::to_string(rc) + ": " +
                           rtrim(read_text(dir + "/run-" + rows[i].key + ".log")));
        double u[3];
        const bool axis = pipe_axis(sc->texts[i], u);
        v[i] = trace_speed(dir + "/run-" + rows[i].key + "/trace.csv", a->window_start_s, axis ? u : nullptr);
      }
    }
    run_wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // the run directories are large (trace, bus log): keep only the first (base) evaluation's
    if (!cache.empty())
      for (size_t i = 0; i < rows.size(); ++i) std::filesystem::remove_all(dir + "/run-" + rows[i].key);
    cache[key] = v;
    return v;
  }
};

// RMS of sim - real over the rows in mask (all when empty), cm/s
double rms(const std::vector<double>& sim, const std::vector<Row>& rows, const std::vector<bool>& mask = {}) {
  double s = 0;
  int n = 0;
  for (size_t i = 0; i < rows.size(); ++i)
    if (mask.empty() || mask[i]) s += (sim[i] - rows[i].real) * (sim[i] - rows[i].real), ++n;
  return n ? std::sqrt(s / n) : 0;
}

struct FitResult {
  Setting st;
  double gap = NAN;
  int evals = 0;
};

// 1-D: a log grid of 7 then golden-section refinement around the best
FitResult fit1(Runner& r, const Setting& fixed, int k, const std::vector<bool>& mask) {
  const Knob& kb = knobs()[k];
  const double a = std::log(kb.lo), b = std::log(kb.hi);
  int evals = 0;
  auto f = [&](double x) {
    Setting st = fixed;
    st[k] = std::exp(x);
    ++evals;
    return rms(r.speeds(st), r.rows, mask);
  };
  const int G = 7;
  double best = INFINITY, bx = 0;
  std::vector<double> xs(G), fs(G);
  for (int i = 0; i < G; ++i) {
    xs[i] = a + (b - a) * i / (G - 1), fs[i] = f(xs[i]);
    if (fs[i] < best) best = fs[i], bx = xs[i];
  }
  const int ib = int(std::min_element(fs.begin(), fs.end()) - fs.begin());
  double lo = xs[std::max(0, ib - 1)], hi = xs[std::min(G - 1, ib + 1)];
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = hi - g * (hi - lo), d = lo + g * (hi - lo), fc = f(c), fd = f(d);
  for (int it = 0; it < 6; ++it) {
    if (fc < fd) hi = d, d = c, fd = fc, c = hi - g * (hi - lo), fc = f(c);
    else lo = c, c = d, fc = fd, d = lo + g * (hi - lo), fd = f(d);
  }
  for (auto [x, v] : {std::pair{c, fc}, std::pair{d, fd}})
    if (v < best) best = v, bx = x;
  FitResult res;
  res.st = fixed;
  res.st[k] = std::exp(bx);
  res.gap = best;
  res.evals = evals;
  return res;
}

// 2-D (or more): NLopt BOBYQA on the log factors, started from start
FitResult fitn(Runner& r, const Setting& start, const std::vector<bool>& mask, int maxeval = 30) {
  std::vector<int> ks;
  std::vector<double> x, lb, ub;
  for (const auto& [k, v] : start) {
    ks.push_back(k);
    x.push_back(std::log(v));
    lb.push_back(std::log(knobs()[k].lo)), ub.push_back(std::log(knobs()[k].hi));
  }
  struct Ctx {
    Runner* r;
    const std::vector<int>* ks;
    const std::vector<bool>* mask;
    int evals = 0;
  } ctx{&r, &ks, &mask};
  auto obj = [](const std::vector<double>& xv, std::vector<double>&, void* p) {
    auto* c = static_cast<Ctx*>(p);
    Setting st;
    for (size_t i = 0; i < xv.size(); ++i) st[(*c->ks)[i]] = std::exp(xv[i]);
    ++c->evals;
    return rms(c->r->speeds(st), c->r->rows, *c->mask);
  };
  nlopt::opt opt(x.size() >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_COBYLA, unsigned(x.size()));
  opt.set_lower_bounds(lb), opt.set_upper_bounds(ub);
  opt.set_min_objective(obj, &ctx);
  opt.set_maxeval(maxeval);
  opt.set_xtol_abs(0.005);
  std::vector<double> step(x.size());
  for (size_t i = 0; i < x.size(); ++i) step[i] = std::min(0.15, 0.25 * (ub[i] - lb[i]));
  opt.set_initial_step(step);
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], lb[i], ub[i]);
  double fx = NAN;
  try {
    opt.optimize(x, fx);
  } catch (const nlopt::roundoff_limited&) {
  } catch (const std::invalid_argument&) {
  }
  FitResult res;
  for (size_t i = 0; i < ks.size(); ++i) res.st[ks[i]] = std::exp(x[i]);
  res.gap = rms(r.speeds(res.st), r.rows, mask);
  // BOBYQA may end worse than where it started
  const double g0 = rms(r.speeds(start), r.rows, mask);
  if (g0 < res.gap) res.st = start, res.gap = g0;
  res.evals = ctx.evals;
  return res;
}

FitResult fit(Runner& r, const Setting& st0, int new_knob, const std::vector<bool>& mask) {
  if (st0.empty()) return fit1(r, {}, new_knob, mask);
  // new knob on its own with the others held, then all jointly
  FitResult one = fit1(r, st0, new_knob, mask);
  FitResult all = fitn(r, one.st, mask);
  all.evals += one.evals;
  return all;
}

constexpr double kMinGainRobot = 0.30;  // an effect must cut the RMS gap by 30 %
constexpr double kTableResolution = 0.05;  // cm/s: the tables give 0.1 cm/s, so +-0.05 is rounding

std::string fmtd(double v, int prec = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", prec, std::fabs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

}  // namespace

int run_robot(const RobotArgs& a) {
  const auto t_start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(); };
  auto say = [&](const std::string& s) {
    if (!a.quiet) std::fprintf(stderr, "chainsim calibrate [%6.1f s] %s\n", elapsed(), s.c_str());
  };
  if (!(a.duration_s > a.window_start_s))
    throw RobotError("--duration (" + fmtd(a.duration_s, 2) + " s) must exceed --window-start (" +
                     fmtd(a.window_start_s, 2) + " s)");
  if (a.scene_template.find("{slope}") == std::string::npos)
    throw RobotError("--scene-template " + a.scene_template + ": needs {slope} (replaced by each row's key)");
  std::string key_name;
  Runner r;
  r.a = &a;
  r.rows = read_table(a.table, &key_name);
  const Scenes sc = load_scenes(a.scene_template, r.rows);
  r.sc = &sc;
  r.exe = self_exe();
  std::error_code ec;
  std::filesystem::create_directories(a.out, ec);
  if (!std::filesystem::is_directory(a.out)) throw RobotError(a.out + ": cannot create the output directory");
  r.work = std::filesystem::absolute(a.out).string() + "/runs";
  std::filesystem::remove_all(r.work, ec);
  std::filesystem::create_directories(r.work);
  const size_t n = r.rows.size();

  say("base: " + std::to_string(n) + " scenes, " + fmtd(a.duration_s, 1) + " s each");
  const auto base = r.speeds({});
  const double gap_before = rms(base, r.rows);
  double paper_gap = NAN;
  {
    bool all = true;
    double s = 0;
    for (const auto& row : r.rows) all = all && std::isfinite(row.paper), s += std::pow(row.paper - row.real, 2);
    if (all) paper_gap = std::sqrt(s / n);
  }
  say("gap before " + fmtd(gap_before) + " cm/s RMS (paper's simulator: " + fmtd(paper_gap) + ")");

  nlohmann::ordered_json jc = nlohmann::ordered_json::array();
  Setting cur;
  double cur_gap = gap_before;
  std::vector<int> accepted;
  // at most n - 2 parameters, so that the fit keeps two degrees of freedom
  const size_t max_params = std::min<size_t>(2, n >= 3 ? n - 2 : 0);
  for (int round = 1; accepted.size() < max_params && cur_gap > kTableResolution; ++round) {
    struct Cand {
      int k;
      FitResult f;
    };
    std::vector<Cand> cands;
    for (int k : sc.usable) {
      if (cur.count(k)) continue;
      Cand c{k, fit(r, cur, k, {})};
      say("round " + std::to_string(round) + ": " + knobs()[k].name + " -> gap " + fmtd(c.f.gap));
      cands.push_back(c);
    }
    if (cands.empty()) break;
    std::sort(cands.begin(), cands.end(), [](const Cand& x, const Cand& y) { return x.f.gap < y.f.gap; });
    bool took = false;
    for (size_t i = 0; i < cands.size(); ++i) {
      const auto& c = cands[i];
      const double fac = c.f.st.at(c.k);
      const bool at_null = std::fabs(std::log(fac)) < 0.01;
      const bool at_bound = fac <= knobs()[c.k].lo * 1.01 || fac >= knobs()[c.k].hi / 1.01;
      std::string why;
      bool acc = false;
      if (i > 0) why = "not the best of the round";
      else if (at_null) why = "fitted to its nominal value";
      else if (c.f.gap > (1 - kMinGainRobot) * cur_gap)
        why = "cuts the gap by " + fmtd(100 * (1 - c.f.gap / cur_gap), 0) + " % (< " +
              fmtd(100 * kMinGainRobot, 0) + " %)";
      else acc = true, why = "accepted";
      if (acc && at_bound) why += " (at a bound of its range)";
      nlohmann::ordered_json jp = nlohmann::ordered_json::object();
      for (const auto& [k, f] : c.f.st)
        jp[knobs()[k].name] = {{"factor", f}, {"value", f * sc.nominal.at(knobs()[k].name)},
                               {"nominal", sc.nominal.at(knobs()[k].name)}};
      jc.push_back({{"round", round}, {"name", knobs()[c.k].name}, {"param", knobs()[c.k].param},
                    {"gap", c.f.gap}, {"settings", jp}, {"evaluations", c.f.evals}, {"accepted", acc}, {"why", why}});
      if (acc) cur = c.f.st, cur_gap = c.f.gap, accepted.push_back(c.k), took = true;
    }
    if (!took) break;
  }
  const auto after = r.speeds(cur);

  // leave-one-row-out check of the accepted effects: refit on the other rows,
  // predict the left-out one
  double loo_gap = NAN;
  std::vector<double> loo(n, NAN);
  if (!accepted.empty() && n >= 3) {
    say("leave-one-row-out check");
    double s = 0;
    for (size_t i = 0; i < n; ++i) {
      std::vector<bool> mask(n, true);
      mask[i] = false;
      Setting st;
      FitResult f;
      for (int k : accepted) f = fit(r, st, k, mask), st = f.st;
      loo[i] = r.speeds(st)[i];
      s += std::pow(loo[i] - r.rows[i].real, 2);
    }
    loo_gap = std::sqrt(s / n);
  }

  const bool explained = cur_gap <= kTableResolution;
  const std::string verdict = accepted.empty() ? (explained ? "no_missing_effect" : "unexplained")
                                               : (explained ? "explained" : "unexplained");
  // what stays: the rows the fitted model misses by more than the table's resolution
  nlohmann::ordered_json jmiss = nlohmann::ordered_json::array();
  for (size_t i = 0; i < n; ++i)
    if (std::fabs(after[i] - r.rows[i].real) > kTableResolution)
      jmiss.push_back({{key_name, r.rows[i].key}, {"real", r.rows[i].real}, {"after", after[i]},
                       {"error", after[i] - r.rows[i].real}});

  nlohmann::ordered_json j;
  j["kind"] = "robot";
  j["table"] = a.table;
  j["scene_template"] = a.scene_template;
  j["key"] = key_name;
  j["duration_s"] = a.duration_s;
  j["window_start_s"] = a.window_start_s;
  j["metric"] = "RMS over the rows of simulated - real speed, cm/s";
  j["verdict"] = verdict;
  j["gap_before"] = gap_before;
  j["gap_after"] = cur_gap;
  j["gap_paper_sim"] = std::isfinite(paper_gap) ? nlohmann::ordered_json(paper_gap) : nlohmann::ordered_json();
  j["gap_leave_one_out"] = std::isfinite(loo_gap) ? nlohmann::ordered_json(loo_gap) : nlohmann::ordered_json();
  j["table_resolution_cm_s"] = kTableResolution;
  nlohmann::ordered_json je = nlohmann::ordered_json::array();
  for (int k : accepted)
    je.push_back({{"name", knobs()[k].name}, {"param", knobs()[k].param}, {"meaning", knobs()[k].meaning},
                  {"nominal", sc.nominal.at(knobs()[k].name)}, {"factor", cur.at(k)},
                  {"value", cur.at(k) * sc.nominal.at(knobs()[k].name)}});
  j["effects"] = je;
  nlohmann::ordered_json tried = nlohmann::ordered_json::array();
  for (int k : sc.usable) tried.push_back(knobs()[k].name);
  j["catalogue_applicable"] = tried;
  nlohmann::ordered_json jr = nlohmann::ordered_json::array();
  for (size_t i = 0; i < n; ++i) {
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
    jr.push_back({{key_name, r.rows[i].key}, {"real", r.rows[i].real}, {"paper_sim", num(r.rows[i].paper)},
                  {"before", base[i]}, {"after", after[i]}, {"leave_one_out", num(loo[i])}});
  }
  j["rows"] = jr;
  j["missed"] = jmiss;
  j["candidates"] = jc;
  j["runs"] = r.runs;
  j["evaluations"] = r.cache.size();
  j["run_wall_s"] = r.run_wall;
  j["wall_s"] = elapsed();
  {
    std::ofstream f(a.out + "/report.json");
    f << j.dump(2) << "\n";
    if (!f) throw RobotError(a.out + "/report.json: cannot write");
  }

  std::ostringstream md;
  md << "# Robot-level calibration report\n\nTable `" << a.table << "`, scenes `" << a.scene_template << "` ("
     << n << " rows; runs of " << fmtd(a.duration_s, 1) << " s, speed of the head along the pipe axis from "
     << fmtd(a.window_start_s, 1) << " s).\n\n**Verdict: " << verdict << "**. Gap (RMS of simulated - real, cm/s): "
     << "before " << fmtd(gap_before) << ", after " << fmtd(cur_gap);
  if (std::isfinite(loo_gap)) md << " (leave-one-row-out " << fmtd(loo_gap) << ")";
  if (std::isfinite(paper_gap)) md << "; the paper's simulator " << fmtd(paper_gap);
  md << ". Table resolution: +-" << kTableResolution << " cm/s.\n\n";
  md << "| " << key_name << " | real | paper's sim | before | after | leave-one-out |\n|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < n; ++i)
    md << "| " << r.rows[i].key << " | " << fmtd(r.rows[i].real, 2) << " | "
       << (std::isfinite(r.rows[i].paper) ? fmtd(r.rows[i].paper, 2) : "-") << " | " << fmtd(base[i], 2) << " | "
       << fmtd(after[i], 2) << " | " << (std::isfinite(loo[i]) ? fmtd(loo[i], 2) : "-") << " |\n";
  md << "\n## Effects\n\n";
  if (accepted.empty()) md << "None accepted.\n";
  for (int k : accepted)
    md << "* `" << knobs()[k].name << "` (" << knobs()[k].meaning << "): " << knobs()[k].param << " "
       << fmtd(sc.nominal.at(knobs()[k].name), 4) << " -> " << fmtd(cur.at(k) * sc.nominal.at(knobs()[k].name), 4)
       << " (x" << fmtd(cur.at(k)) << ")\n";
  if (!jmiss.empty()) {
    md << "\nStill missed by more than the table's resolution:";
    for (const auto& m : jmiss)
      md << " " << m[key_name].get<std::string>() << " (" << fmtd(m["error"].get<double>(), 2) << " cm/s)";
    md << ". No effect of the catalogue explains it.\n";
  }
  md << "\n## Candidates\n\n| round | effect | gap after fit | setting | evaluations | decision |\n|---|---|---|---|---|---|\n";
  for (const auto& c : jc) {
    std::string s;
    for (auto it = c["settings"].begin(); it != c["settings"].end(); ++it)
      s += it.key() + " = " + fmtd((*it)["value"].get<double>(), 4) + " ";
    md << "| " << c["round"].get<int>() << " | " << c["name"].get<std::string>() << " | "
       << fmtd(c["gap"].get<double>()) << " | " << s << "| " << c["evaluations"].get<int>() << " | "
       << c["why"].get<std::string>() << " |\n";
  }
  md << "\n" << r.runs << " runs (" << r.cache.size() << " settings), " << fmtd(elapsed(), 1) << " s wall.\n";
  {
    std::ofstream f(a.out + "/report.md");
    f << md.str();
    if (!f) throw RobotError(a.out + "/report.md: cannot write");
  }
  say("verdict " + verdict + ": gap " + fmtd(gap_before) + " -> " + fmtd(cur_gap) + " cm/s; wrote " + a.out +
      "/report.json, report.md");
  return 0;
}

}  // namespace robotcal
}  // namespace chainsim
