// `chainsim bench`: the servo test stand. See bench_command.h and
// docs/servo-bench.md.
//
// The stand is an ODE world of its own: a rotor body on a hinge to the static
// environment (the fixed base), no gravity, the rotor's moment of inertia
// about the axis = the bench's load inertia. The servo is the robot's
// ServoModel (servo_model.h) coupled exactly as the World couples it: a
// one-axis angular motor on the hinge with dParamVel / dParamCFM from the
// model's step law (an implicit damper; see servo_model.h). The constant
// external torque is added to the hinge every step. The stand steps with
// dWorldStep (ODE's exact LCP solver; one body, so it costs nothing) rather
// than the robot's QuickStep, whose unconverged iterations would only add
// solver noise to a bench meant for comparing with the continuous model.
//
// Angles: the bench angle is the hinge angle in degrees, continuous (no stops,
// no wrap at +-180), so the paper's 30 -> 120 degree test is written as is.
// The hinge starts at rest at the first set-point.
#include "chainsim/bench_command.h"

#include <CLI/CLI.hpp>
#include <ode/ode.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "physics/actuators/servo_model.h"

namespace chainsim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMotorFMax = 10.0;        // N m, far above any servo torque (as the World)
constexpr double kMaxSpan_s = 10000.0;     // longest set-point file accepted, simulated seconds
constexpr double kEpsUs = 1e-3;            // time tolerance, microseconds


// ---------------------------------------------------------------- bench file

struct Yctx {
  const std::string& file;
};

std::string where(const Yctx& c, const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  std::ostringstream s;
  s << c.file;
  if (m.line >= 0) s << ":" << (m.line + 1) << ":" << (m.column + 1);
  return s.str();
}

[[noreturn]] void yfail(const Yctx& c, const YAML::Node& n, const std::string& what) {
  throw BenchError(where(c, n) + ": " + what);
}

void check_keys(const Yctx& c, const YAML::Node& map, const std::string& path,
                const std::vector<std::string>& allowed) {
  if (!map.IsMap()) yfail(c, map, "'" + path + "' must be a mapping");
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string known;
      for (const auto& a : allowed) known += (known.empty() ? "" : ", ") + a;
      yfail(c, kv.first,
            "unknown key '" + key + "' in '" + path + "' (known: " + known + ")");
    }
  }
}

// the value of key in map (unchanged when absent), a finite number in [lo, hi]
// (lo excluded when lo_open)
void get_number(const Yctx& c, const YAML::Node& map, const std::string& path,
                const std::string& key, double lo, bool lo_open, double hi, double* out) {
  const YAML::Node n = map[key];
  if (!n) return;
  const std::string name = "'" + path + "." + key + "'";
  double v = 0;
  if (!n.IsScalar()) yfail(c, n, name + " must be a number");
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    yfail(c, n, name + " must be a number, not '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) yfail(c, n, name + " must be a finite number, not '" + n.Scalar() + "'");
  if (v < lo || (lo_open && v == lo) || v > hi) {
    std::ostringstream s;
    s << name << " = " << n.Scalar() << " is out of range " << (lo_open ? "(" : "[") << lo << ", "
      << hi << "]";
    yfail(c, n, s.str());
  }
  *out = v;
}

BenchConfig load_bench_file(const std::string& file) {
  BenchConfig b;
  std::ifstream in(file, std::ios::binary);
  if (!in) throw BenchError(file + ": cannot open the bench file");
  std::stringstream text;
  text << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::ParserException& e) {
    std::ostringstream s;
    s << file << ":" << (e.mark.line + 1) << ":" << (e.mark.column + 1) << ": YAML syntax error: " << e.msg;
    throw BenchError(s.str());
  }
  const Yctx c{file};
  if (!root || root.IsNull()) return b;  // empty file: all defaults
  check_keys(c, root, "bench file", {"servo", "load", "sensors", "sim"});
  ServoParams& p = b.servo;
  if (const YAML::Node n = root["servo"]; n && !n.IsNull()) {
    check_keys(c, n, "servo",
               {"Kp", "Km", "Kt", "R", "L", "B", "J", "supply_v", "i_threshold_a", "coulomb_nm",
                "backlash_deg", "deadband_deg", "supply_sag_ohm", "pwm_frame_s", "current_limit_a"});
    get_number(c, n, "servo", "Kp", 0, false, 1e6, &p.kp);
    get_number(c, n, "servo", "Km", 0, false, 1e3, &p.km);
    get_number(c, n, "servo", "Kt", 0, false, 1e3, &p.kt);
    get_number(c, n, "servo", "R", 0, true, 1e6, &p.r);
    get_number(c, n, "servo", "L", 0, false, 10, &p.l);
    get_number(c, n, "servo", "B", 0, false, 1e3, &p.b);
    get_number(c, n, "servo", "J", 0, false, 1e3, &p.j);
    get_number(c, n, "servo", "supply_v", 0, false, 1e3, &p.supply_v);
    get_number(c, n, "servo", "i_threshold_a", 0, false, 1e3, &p.i_threshold_a);
    get_number(c, n, "servo", "coulomb_nm", 0, false, 1e3, &p.coulomb_nm);
    get_number(c, n, "servo", "backlash_deg", 0, false, 90, &p.backlash_deg);
    get_number(c, n, "servo", "deadband_deg", 0, false, 90, &p.deadband_deg);
    get_number(c, n, "servo", "supply_sag_ohm", 0, false, 1e6, &p.supply_sag_ohm);
    get_number(c, n, "servo", "pwm_frame_s", 0, false, 10, &p.pwm_frame_s);
    get_number(c, n, "servo", "current_limit_a", 0, false, 1e3, &p.current_limit_a);
  }
  if (const YAML::Node n = root["load"]; n && !n.IsNull()) {
    check_keys(c, n, "load", {"inertia_kgm2", "torque_nm"});
    get_number(c, n, "load", "inertia_kgm2", 0, false, 1e3, &b.load_inertia_kgm2);
    get_number(c, n, "load", "torque_nm", -1e3, false, 1e3, &b.load_torque_nm);
  }
  if (const YAML::Node n = root["sensors"]; n && !n.IsNull()) {
    check_keys(c, n, "sensors", {"current_filter_tau_s"});
    get_number(c, n, "sensors", "current_filter_tau_s", 0, false, 100, &p.current_filter_tau_s);
  }
  if (const YAML::Node n = root["sim"]; n && !n.IsNull()) {
    check_keys(c, n, "sim", {"dt_us"});
    if (const YAML::Node d = n["dt_us"]) {
      int64_t v = 0;
      try {
        v = d.as<int64_t>();
      } catch (const YAML::Exception&) {
        yfail(c, d, "'sim.dt_us' must be an integer (microseconds), not '" + d.Scalar() + "'");
      }
      if (v < 1 || v > 100000)
        yfail(c, d, "'sim.dt_us' = " + d.Scalar() + " is out of range [1, 100000]");
      b.dt_us = v;
    }
  }
  if (!(p.j + b.load_inertia_kgm2 > 0)) {
    const YAML::Node n = root["load"] ? root["load"] : root;
    yfail(c, n, "'servo.J' + 'load.inertia_kgm2' must be > 0 (something has to turn)");
  }
  return b;
}

// ---------------------------------------------------------------- set-point CSV

struct Row {
  double t_s = 0;
  double setpoint_deg = 0;
};

std::string trim(const std::string& s, size_t* lead = nullptr) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  if (lead) *lead = a;
  return s.substr(a, b - a);
}

struct Cell {
  std::string text;   // trimmed
  int column = 1;     // 1-based character column of the cell's first character
};

std::vector<Cell> split(const std::string& line) {
  std::vector<Cell> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    const std::string raw = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t lead = 0;
    Cell c;
    c.text = trim(raw, &lead);
    c.column = static_cast<int>(start + lead) + 1;
    out.push_back(c);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<Row> read_setpoints(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw BenchError(file + ": cannot open the set-point file");
  auto fail = [&](int line, int col, const std::string& what) -> BenchError {
    return BenchError(file + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + what);
  };
  std::string line;
  int lineno = 0;
  int t_col = -1, sp_col = -1;
  std::vector<Row> rows;
  int prev_line = 0;
  std::string prev_text;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    if (lineno == 1) {
      std::vector<Cell> cells = split(line);
      std::set<std::string> seen;
      std::string names;
      for (size_t k = 0; k < cells.size(); ++k) {
        std::string n = cells[k].text;
        if (n.size() >= 2 && n.front() == '"' && n.back() == '"') n = n.substr(1, n.size() - 2);
        if (!n.empty() && !seen.insert(n).second)
          throw fail(lineno, cells[k].column, "column '" + n + "' appears twice in the header");
        names += (names.empty() ? "" : ", ") + n;
        if (n == "t_s") t_col = static_cast<int>(k);
        if (n == "setpoint_deg") sp_col = static_cast<int>(k);
      }
      for (const auto& [col, name] : {std::pair{t_col, "t_s"}, std::pair{sp_col, "setpoint_deg"}})
        if (col < 0)
          throw fail(1, 1, std::string("missing column '") + name +
                               "' in the header (the header has: " + names +
                               "; needed: t_s, setpoint_deg)");
      continue;
    }
    if (trim(line).empty()) continue;  // blank lines are ignored
    const std::vector<Cell> cells = split(line);
    Row r;
    for (const auto& [col, name, dst] :
         {std::tuple{t_col, "t_s", &r.t_s}, std::tuple{sp_col, "setpoint_deg", &r.setpoint_deg}}) {
      if (col >= static_cast<int>(cells.size()))
        throw fail(lineno, static_cast<int>(line.size()) + 1,
                   std::string("missing column '") + name + "' (this row has " +
                       std::to_string(cells.size()) + " cells)");
      const Cell& c = cells[col];
      if (c.text.empty()) throw fail(lineno, c.column, std::string("empty cell in column '") + name + "'");
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(c.text.c_str(), &end);
      if (end != c.text.c_str() + c.text.size())
        throw fail(lineno, c.column,
                   std::string("'") + c.text + "' in column '" + name + "' is not a number");
      if (!std::isfinite(v))
        throw fail(lineno, c.column,
                   std::string("'") + c.text + "' in column '" + name + "' is not a finite number");
      *dst = v;
    }
    if (!rows.empty() && !(r.t_s > rows.back().t_s))
      throw fail(lineno, cells[t_col].column,
                 "t_s = " + cells[t_col].text + " is not after the previous row's " + prev_text +
                     " (line " + std::to_string(prev_line) + "): times must be strictly increasing");
    if (!rows.empty() && r.t_s - rows.front().t_s > kMaxSpan_s)
      throw fail(lineno, cells[t_col].column,
                 "the set-points span more than " + std::to_string(static_cast<int>(kMaxSpan_s)) +
                     " s from the first row");
    prev_line = lineno;
    prev_text = cells[t_col].text;
    rows.push_back(r);
  }
  if (lineno == 0) throw fail(1, 1, "empty file: expected a header line naming the columns t_s and setpoint_deg");
  if (rows.empty()) throw fail(lineno, 1, "no rows of data after the header");
  return rows;
}

// ---------------------------------------------------------------- the stand

struct Sample {
  double angle_deg = 0;
  double current_a = 0;
};

class Stand {
 public:
  Stand(const BenchConfig& b, BenchSolver solver)
      : cfg_(b), model_(b.servo), h_(b.dt_us * 1e-6), solver_(solver) {
    jl_ = std::max(b.load_inertia_kgm2, 1e-12);
    if (solver_ == BenchSolver::closed_form) return;
    dInitODE2(0);
    dAllocateODEDataForThread(dAllocateMaskAll);
    world_ = dWorldCreate();
    dWorldSetGravity(world_, 0, 0, 0);
    dWorldSetERP(world_, 0.2);
    dWorldSetCFM(world_, 1e-9);
    dWorldSetAutoDisableFlag(world_, 0);
    rotor_ = dBodyCreate(world_);
    // the load inertia about the axis (z); ODE needs a positive inertia, so a
    // zero load gets 1e-12 kg m^2 (the servo's own J is in the model)
    const double jl = std::max(b.load_inertia_kgm2, 1e-12);
    dMass m;
    dMassSetParameters(&m, 0.01, 0, 0, 0, jl, jl, jl, 0, 0, 0);
    dBodySetMass(rotor_, &m);
    hinge_ = dJointCreateHinge(world_, nullptr);
    dJointAttach(hinge_, rotor_, nullptr);
    dJointSetHingeAnchor(hinge_, 0, 0, 0);
    dJointSetHingeAxis(hinge_, 0, 0, 1);
    motor_ = dJointCreateAMotor(world_, nullptr);
    dJointAttach(motor_, rotor_, nullptr);
    dJointSetAMotorMode(motor_, dAMotorUser);
    dJointSetAMotorNumAxes(motor_, 1);
    dJointSetAMotorAxis(motor_, 0, 0, 0, 0, 1);
    dJointSetAMotorParam(motor_, dParamFMax, kMotorFMax);
  }
  ~Stand() {
    if (world_) dWorldDestroy(world_);
  }
  Stand(const Stand&) = delete;
  Stand& operator=(const Stand&) = delete;

  // model angles are relative to the start (the hinge's 0); the bench adds
  // the first set-point back
  void set_setpoint_rad(double rel) { model_.set_setpoint(rel); }

  void step() {
    if (solver_ == BenchSolver::closed_form) {
      // one degree of freedom: (Jl/h + D) w' = Jl w/h + D v + tau_load, then
      // theta += h w' (ODE's semi-implicit position update)
      const ServoModel::StepLaw law = model_.begin_step(theta_, w_, h_);
      const double jh = jl_ / h_;
      w_ = (jh * w_ + law.damping * law.target_rate + cfg_.load_torque_nm) / (jh + law.damping);
      model_.end_step(w_);
      theta_ += h_ * w_;
      return;
    }
    const double w = dJointGetHingeAngleRate(hinge_);
    const ServoModel::StepLaw law = model_.begin_step(theta_, w, h_);
    dJointSetAMotorParam(motor_, dParamVel, law.target_rate);
    dJointSetAMotorParam(motor_, dParamCFM, 1.0 / law.damping);
    if (cfg_.load_torque_nm != 0.0) dJointAddHingeTorque(hinge_, cfg_.load_torque_nm);
    dWorldStep(world_, h_);
    model_.end_step(dJointGetHingeAngleRate(hinge_));
    // unwrap: ODE's hinge angle is in (-pi, pi]
    const double a = dJointGetHingeAngle(hinge_);
    double d = a - last_raw_;
    if (d > kPi) d -= 2 * kPi;
    if (d < -kPi) d += 2 * kPi;
    theta_ += d;
    last_raw_ = a;
  }

  double theta_rad() const { return theta_; }
  double filtered_current_a() const { return model_.filtered_current_a(); }

 private:
  BenchConfig cfg_;
  ServoModel model_;
  double h_;
  BenchSolver solver_;
  double jl_ = 0, w_ = 0;   // closed form: load inertia, hinge rate
  dWorldID world_ = nullptr;
  dBodyID rotor_ = nullptr;
  dJointID hinge_ = nullptr, motor_ = nullptr;
  double theta_ = 0, last_raw_ = 0;
};

std::vector<Sample> run_bench(const BenchConfig& b, const std::vector<Row>& rows,
                              BenchSolver solver = BenchSolver::ode_exact) {
  Stand stand(b, solver);
  const double deg = kPi / 180.0;
  const double sp0 = rows.front().setpoint_deg;
  const double dt = static_cast<double>(b.dt_us);
  auto rel_us = [&](size_t k) { return (rows[k].t_s - rows.front().t_s) * 1e6; };
  auto state = [&] { return Sample{sp0 + stand.theta_rad() / deg, stand.filtered_current_a()}; };
  std::vector<Sample> out;
  out.reserve(rows.size());
  Sample prev = state(), cur = prev;
  out.push_back(cur);
  int64_t n = 0;        // steps done: the state is that of time n dt
  size_t active = 0;    // the row whose set-point is applied
  for (size_t k = 1; k < rows.size(); ++k) {
    const double tk = rel_us(k);
    while (static_cast<double>(n) * dt < tk - kEpsUs) {
      // set-point of step n: the last row at or before its start
      while (active + 1 < rows.size() && rel_us(active + 1) <= static_cast<double>(n) * dt + kEpsUs)
        ++active;
      stand.set_setpoint_rad((rows[active].setpoint_deg - sp0) * deg);
      stand.step();
      prev = cur;
      cur = state();
      ++n;
    }
    // (n-1) dt < tk <= n dt: linear between the two step ends
    const double tn = static_cast<double>(n) * dt;
    if (n == 0 || std::fabs(tn - tk) <= kEpsUs) {
      out.push_back(cur);
    } else {
      const double f = (tk - (tn - dt)) / dt;
      out.push_back({prev.angle_deg + f * (cur.angle_deg - prev.angle_deg),
                     prev.current_a + f * (cur.current_a - prev.current_a)});
    }
  }
  return out;
}

// fixed formatting; no "-0.0000"
void put(std::string* s, const char* fmt, double v, double zero) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, std::fabs(v) < zero ? 0.0 : v);
  *s += buf;
}

std::string format_output(const std::vector<Row>& rows, const std::vector<Sample>& samples) {
  std::string s = "t_s,setpoint_deg,angle_deg,current_a\n";
  s.reserve(rows.size() * 40 + 64);
  for (size_t k = 0; k < rows.size(); ++k) {
    put(&s, "%.6f", rows[k].t_s, 5e-7);
    put(&s, ",%.4f", rows[k].setpoint_deg, 5e-5);
    put(&s, ",%.4f", samples[k].angle_deg, 5e-5);
    put(&s, ",%.6f\n", samples[k].current_a, 5e-7);
  }
  return s;
}

// ---------------------------------------------------------------- the command

struct BenchArgs {
  std::string bench;
  std::string setpoints;
  std::string out;
  bool quiet = false;
};

BenchArgs g_args;
int g_exit_code = -1;

int run_bench_command(const BenchArgs& a) {
  try {
    const BenchConfig b = a.bench.empty() ? BenchConfig{} : load_bench_file(a.bench);
    const std::vector<Row> rows = read_setpoints(a.setpoints);
    const std::vector<Sample> samples = run_bench(b, rows);
    const std::string text = format_output(rows, samples);
    std::FILE* f = std::fopen(a.out.c_str(), "wb");
    if (!f) throw BenchError(a.out + ": cannot write the output file");
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (std::fclose(f) != 0 || !ok) throw BenchError(a.out + ": cannot write the output file");
    if (!a.quiet)
      std::fprintf(stderr, "chainsim bench: %zu rows, %.6f s simulated at dt %lld us -> %s\n",
                   rows.size(), rows.back().t_s - rows.front().t_s,
                   static_cast<long long>(b.dt_us), a.out.c_str());
    return 0;
  } catch (const BenchError& e) {
    std::fprintf(stderr, "chainsim bench: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim bench: internal error: %s\n", e.what());
    return 3;
  }
}

}  // namespace

void add_bench_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "bench",
      "servo test stand: the robot's servo model on one hinge with a load, driven by a set-point "
      "CSV (t_s,setpoint_deg); writes t_s,setpoint_deg,angle_deg,current_a (docs/servo-bench.md)");
  sub->add_option("--bench,-b", g_args.bench,
                  "bench file (YAML: servo, load, sensors, sim; every key optional; default: the "
                  "paper's Table 1 servo with a 3e-6 kg m^2 load)");
  sub->add_option("--setpoints,-s", g_args.setpoints, "set-point CSV with columns t_s,setpoint_deg")
      ->required();
  sub->add_option("--out,-o", g_args.out, "CSV to write: t_s,setpoint_deg,angle_deg,current_a")
      ->required();
  sub->add_flag("--quiet,-q", g_args.quiet, "print only errors");
  sub->callback([] { g_exit_code = run_bench_command(g_args); });
}

int bench_command_exit_code() { return g_exit_code; }

BenchConfig load_bench_config(const std::string& file) { return load_bench_file(file); }

std::vector<BenchSample> simulate_bench(const BenchConfig& b, const std::vector<double>& t_s,
                                        const std::vector<double>& setpoint_deg, BenchSolver solver) {
  if (t_s.empty() || t_s.size() != setpoint_deg.size())
    throw std::invalid_argument("simulate_bench: t_s and setpoint_deg must be non-empty, same length");
  std::vector<Row> rows(t_s.size());
  for (size_t k = 0; k < t_s.size(); ++k) rows[k] = {t_s[k], setpoint_deg[k]};
  const std::vector<Sample> s = run_bench(b, rows, solver);
  std::vector<BenchSample> out(s.size());
  for (size_t k = 0; k < s.size(); ++k) out[k] = {s[k].angle_deg, s[k].current_a};
  return out;
}

}  // namespace chainsim
