// `chainsim bench` run as a user runs it (a process), checked against the
// paper's Fig. 4 shape and against an independent fine-step RK4 solution of
// the continuous servo equations written here (not the model's code), plus the
// file errors (file:line:column).
//
// Continuous model (docs/servo-bench.md), bench angle theta in rad:
//   ea    = clamp(Kp (theta_r - theta), -Vs, Vs)
//   L di/dt = ea - R i - Km w
//   (J + J_load) dw/dt = Kt dz(i) - B w + tau_load      dz: dead zone of width I_th
//   tau_f di_f/dt = |i| - i_f                            (the bench's current_a = i_f)
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

// ------------------------------------------------------------------ helpers

class TempDir {
 public:
  TempDir() {
    char tmpl[] = "/tmp/chainsim-bench-test-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (!d) std::abort();
    path_ = d;
  }
  ~TempDir() { std::system(("rm -rf '" + path_ + "'").c_str()); }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary) << text;
    return file(name);
  }

 private:
  std::string path_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  int exit_code = -1;
  std::string err;
};

// runs chainsim bench with these arguments (each single-quoted), stderr captured
Result bench(const TempDir& dir, const std::vector<std::string>& args) {
  std::string cmd = std::string("'") + CHAINSIM_EXE + "' bench";
  for (const std::string& a : args) cmd += " '" + a + "'";
  cmd += " 2> '" + dir.file("stderr.txt") + "'";
  const int st = std::system(cmd.c_str());
  Result r;
  r.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.err = slurp(dir.file("stderr.txt"));
  return r;
}

struct Table {
  std::string header;
  std::vector<double> t, sp, angle, current;
};

Table read_output(const std::string& path) {
  Table tb;
  std::ifstream in(path);
  std::getline(in, tb.header);
  std::string line;
  while (std::getline(in, line)) {
    double v[4];
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3]) != 4) {
      ADD_FAILURE() << "bad output line: " << line;
      break;
    }
    tb.t.push_back(v[0]);
    tb.sp.push_back(v[1]);
    tb.angle.push_back(v[2]);
    tb.current.push_back(v[3]);
  }
  return tb;
}

// ------------------------------------------------------------------ reference

struct Params {
  double kp = 12.0, km = 0.14, kt = 0.14, r = 12.0, l = 0.0075, b = 3.5e-6, j = 7.0e-7;
  double vs = 5.0, i_th = 0.0;
  double j_load = 3.0e-6, tau_load = 0.0, tau_f = 0.003;
};

// RK4 with a 1 us step of the continuous equations above, from rest at the
// first set-point; set-point piecewise constant (the last row at or before t);
// sampled at the given times (which must lie on the 1 us grid)
void reference(const Params& p, const std::vector<double>& t_rows, const std::vector<double>& sp_deg,
               std::vector<double>* angle_deg, std::vector<double>* current_a) {
  const double h = 1e-6, deg = kPi / 180.0;
  double x[4] = {sp_deg[0] * deg, 0.0, 0.0, 0.0};  // theta, w, i, i_f
  double sp = sp_deg[0] * deg;
  auto f = [&](const double* s, double* d) {
    const double ea = std::clamp(p.kp * (sp - s[0]), -p.vs, p.vs);
    const double i = s[2];
    const double i_eff = i > p.i_th ? i - p.i_th : (i < -p.i_th ? i + p.i_th : 0.0);
    d[0] = s[1];
    d[1] = (p.kt * i_eff - p.b * s[1] + p.tau_load) / (p.j + p.j_load);
    d[2] = (ea - p.r * i - p.km * s[1]) / p.l;
    d[3] = (std::fabs(i) - s[3]) / p.tau_f;
  };
  angle_deg->clear();
  current_a->clear();
  const double t0 = t_rows[0];
  long n = 0;
  size_t active = 0;
  for (size_t k = 0; k < t_rows.size(); ++k) {
    const long target = std::lround((t_rows[k] - t0) / h);
    while (n < target) {
      while (active + 1 < t_rows.size() && std::lround((t_rows[active + 1] - t0) / h) <= n) ++active;
      sp = sp_deg[active] * deg;
      double k1[4], k2[4], k3[4], k4[4], y[4];
      f(x, k1);
      for (int q = 0; q < 4; ++q) y[q] = x[q] + h / 2 * k1[q];
      f(y, k2);
      for (int q = 0; q < 4; ++q) y[q] = x[q] + h / 2 * k2[q];
      f(y, k3);
      for (int q = 0; q < 4; ++q) y[q] = x[q] + h * k3[q];
      f(y, k4);
      for (int q = 0; q < 4; ++q) x[q] += h / 6 * (k1[q] + 2 * k2[q] + 2 * k3[q] + k4[q]);
      ++n;
    }
    angle_deg->push_back(x[0] / deg);
    current_a->push_back(x[3]);
  }
}

double rms_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t k = 0; k < a.size(); ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(s / static_cast<double>(a.size()));
}
double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (size_t k = 0; k < a.size(); ++k) m = std::max(m, std::fabs(a[k] - b[k]));
  return m;
}

const std::string kScenes = std::string(CHAINSIM_SOURCE_DIR) + "/scenes/bench/";

// ------------------------------------------------------------------ tests

// paper Fig. 4: 30 -> 120 degrees, unloaded (only the stand's light load),
// with the shipped files
TEST(ServoBench, Fig4StepShapeAndContinuousReference) {
  TempDir dir;
  const std::string out = dir.file("out.csv");
  const Result r = bench(dir, {"--bench", kScenes + "servo-default.yaml", "--setpoints",
                               kScenes + "step-30-120.csv", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Table tb = read_output(out);
  EXPECT_EQ(tb.header, "t_s,setpoint_deg,angle_deg,current_a");
  ASSERT_EQ(tb.t.size(), 301u);
  for (size_t k = 0; k < tb.t.size(); ++k) {
    ASSERT_NEAR(tb.t[k], k * 1e-3, 1e-9);
    ASSERT_EQ(tb.sp[k], k < 20 ? 30.0 : 120.0);
  }

  // shape: at rest at 30 until the step at 20 ms; then the current peaks at
  // once (towards the stall current 0.42 A, behind the 3 ms filter), falls
  // while the motor runs near its no-load speed, rises again while it brakes
  // (negative current, the filter sees |i|), and settles to ~0 at 120 degrees
  for (size_t k = 0; k <= 20; ++k) {
    EXPECT_EQ(tb.angle[k], 30.0);
    EXPECT_EQ(tb.current[k], 0.0);
  }
  const size_t peak = std::max_element(tb.current.begin(), tb.current.end()) - tb.current.begin();
  size_t dip = peak;
  for (size_t k = peak; k < tb.t.size() && tb.angle[k] < 110; ++k)
    if (tb.current[k] < tb.current[dip]) dip = k;
  size_t brake = dip;
  for (size_t k = dip; k < tb.t.size(); ++k)
    if (tb.current[k] > tb.current[brake]) brake = k;
  size_t reach = 0;  // within 1 degree of 120
  while (reach < tb.t.size() && std::fabs(tb.angle[reach] - 120) > 1) ++reach;
  const double overshoot = *std::max_element(tb.angle.begin(), tb.angle.end()) - 120;
  std::printf("bench Fig. 4: filtered current peak %.4f A at %.0f ms, dip %.4f A at %.0f ms, braking "
              "bump %.4f A at %.0f ms, within 1 deg at %.0f ms, overshoot %.3f deg, final %.4f deg "
              "%.6f A\n",
              tb.current[peak], tb.t[peak] * 1e3, tb.current[dip], tb.t[dip] * 1e3,
              tb.current[brake], tb.t[brake] * 1e3, tb.t[reach] * 1e3, overshoot, tb.angle.back(),
              tb.current.back());
  EXPECT_GT(tb.t[peak], 0.020);
  EXPECT_LT(tb.t[peak], 0.030);            // at the start of the move
  // (the raw current peaks at 0.30 A 1.2 ms after the step, briefly; the
  // 3 ms filter shows ~0.14 A)
  EXPECT_GT(tb.current[peak], 0.1);
  EXPECT_LT(tb.current[peak], 5.0 / 12.0);
  EXPECT_LT(tb.current[dip], 0.1 * tb.current[peak]);           // running near no-load speed
  EXPECT_GT(tb.current[brake], tb.current[dip] + 0.02);          // braking
  EXPECT_GT(tb.t[brake], tb.t[dip]);
  EXPECT_LT(reach, tb.t.size());
  EXPECT_LT(tb.t[brake], tb.t[reach]);
  EXPECT_GT(tb.angle[brake], 100.0);                             // near the end of the move
  EXPECT_LT(overshoot, 1.0);
  EXPECT_NEAR(tb.angle.back(), 120.0, 0.1);
  EXPECT_LT(tb.current.back(), 1e-3);

  // the continuous equations, Table 1 and the stand's defaults (load 3e-6 kg m^2)
  std::vector<double> ra, rc;
  reference(Params{}, tb.t, tb.sp, &ra, &rc);
  const double e_angle = rms_diff(tb.angle, ra), e_current = rms_diff(tb.current, rc);
  std::printf("bench vs RK4 (1 us): angle RMS %.4f deg (max %.4f), current RMS %.3f mA (max %.3f)\n",
              e_angle, max_diff(tb.angle, ra), e_current * 1e3, max_diff(tb.current, rc) * 1e3);
  EXPECT_LT(e_angle, 0.5);
  EXPECT_LT(e_current, 0.003);

  // the same input gives the same bytes
  const std::string out2 = dir.file("out2.csv");
  ASSERT_EQ(bench(dir, {"--bench", kScenes + "servo-default.yaml", "--setpoints",
                        kScenes + "step-30-120.csv", "--out", out2, "--quiet"})
                .exit_code,
            0);
  EXPECT_EQ(slurp(out), slurp(out2));
  // no bench file = the same defaults
  const std::string out3 = dir.file("out3.csv");
  ASSERT_EQ(bench(dir, {"--setpoints", kScenes + "step-30-120.csv", "--out", out3}).exit_code, 0);
  EXPECT_EQ(slurp(out), slurp(out3));
}

// a heavier load with a constant external torque, several moves, the static
// friction threshold and a finer step: still the continuous model
TEST(ServoBench, LoadedMovesAgreeWithTheContinuousReference) {
  TempDir dir;
  std::string csv = "t_s,setpoint_deg\n";
  for (int k = 0; k <= 800; ++k)
    csv += std::to_string(k * 1e-3) + "," + (k < 10 ? "0" : k < 300 ? "90" : k < 550 ? "-45" : "10") + "\n";
  const std::string sp = dir.write("moves.csv", csv);
  struct Case {
    const char* yaml;
    Params p;
  };
  Params loaded;
  loaded.j_load = 2e-5;
  loaded.tau_load = -0.01;
  Params friction = loaded;
  friction.i_th = 0.03;
  Params fine = loaded;
  const Case cases[] = {
      {"load: {inertia_kgm2: 2.0e-5, torque_nm: -0.01}\n", loaded},
      {"servo: {i_threshold_a: 0.03}\nload: {inertia_kgm2: 2.0e-5, torque_nm: -0.01}\n", friction},
      {"load: {inertia_kgm2: 2.0e-5, torque_nm: -0.01}\nsim: {dt_us: 100}\n", fine},
  };
  double prev_angle_err = 1e9;
  for (const Case& c : cases) {
    const std::string yaml = dir.write("b.yaml", c.yaml);
    const Result r = bench(dir, {"--bench", yaml, "--setpoints", sp, "--out", dir.file("o.csv")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Table tb = read_output(dir.file("o.csv"));
    ASSERT_EQ(tb.t.size(), 801u);
    std::vector<double> ra, rc;
    reference(c.p, tb.t, tb.sp, &ra, &rc);
    const double ea = rms_diff(tb.angle, ra), ec = rms_diff(tb.current, rc);
    std::printf("%s-> angle RMS %.4f deg (max %.4f), current RMS %.3f mA (max %.3f); final %.3f deg\n",
                c.yaml, ea, max_diff(tb.angle, ra), ec * 1e3, max_diff(tb.current, rc) * 1e3,
                tb.angle.back());
    EXPECT_LT(ea, 0.5);
    EXPECT_LT(ec, 0.003);
    if (c.p.i_th == 0) {
      // a proportional servo under a constant torque: 10 + tau R / (Kt Kp)
      EXPECT_NEAR(tb.angle.back(), 10 + c.p.tau_load * c.p.r / (c.p.kt * c.p.kp) * 180 / kPi, 0.05);
    }
    if (&c == &cases[2]) {
      EXPECT_LT(ea, prev_angle_err);  // the finer step is closer
    }
    if (&c == &cases[0]) prev_angle_err = ea;
  }
}

// columns found by name, in any order, extra ones ignored, any sample times;
// the output has the input's times
TEST(ServoBench, ColumnsByNameAndAnySampleTimes) {
  TempDir dir;
  const std::string sp = dir.write(
      "s.csv",
      "note, setpoint_deg ,extra,t_s\r\n"
      "start,30,x,1.0\r\n"
      "\r\n"
      "go,120,y,1.0203\r\n"
      "-,120,,1.0213\r\n"
      "-,120,,1.1\r\n"
      "-,120,,1.3\r\n");
  const Result r = bench(dir, {"--setpoints", sp, "--out", dir.file("o.csv")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = slurp(dir.file("o.csv"));
  const Table tb = read_output(dir.file("o.csv"));
  ASSERT_EQ(tb.t.size(), 5u) << text;
  EXPECT_EQ(text.substr(0, text.find('\n', text.find('\n') + 1) + 1),
            "t_s,setpoint_deg,angle_deg,current_a\n1.000000,30.0000,30.0000,0.000000\n");
  EXPECT_DOUBLE_EQ(tb.t[1], 1.0203);
  EXPECT_EQ(tb.angle[1], 30.0);   // the new set-point acts from the next step (at 1.0205 s)
  EXPECT_GT(tb.angle[2], 30.0);
  EXPECT_NEAR(tb.angle.back(), 120.0, 0.1);
}

struct BadCase {
  const char* what;
  const char* csv;      // nullptr: the shipped step file
  const char* yaml;     // nullptr: no --bench
  const char* expect;   // must appear in the message (after the directory)
  const char* expect2;
};

TEST(ServoBench, BadFilesNameFileLineAndColumn) {
  const BadCase cases[] = {
      {"missing column", "t_s,angle_deg\n0,30\n", nullptr, "/s.csv:1:1: ", "'setpoint_deg'"},
      {"non-numeric cell", "t_s,setpoint_deg\n0,30\n0.001,3x0\n", nullptr, "/s.csv:3:7: ",
       "'3x0' in column 'setpoint_deg' is not a number"},
      {"non-numeric time", "setpoint_deg,t_s\n30,0\n30, zero\n", nullptr, "/s.csv:3:5: ",
       "column 't_s'"},
      {"time not increasing", "t_s,setpoint_deg\n0,30\n0.001,30\n0.001,40\n", nullptr, "/s.csv:4:1: ",
       "strictly increasing"},
      {"time going back", "t_s,setpoint_deg\n0,30\n0.002,30\n0.001,40\n", nullptr, "/s.csv:4:1: ",
       "strictly increasing"},
      {"NaN", "t_s,setpoint_deg\n0,30\n0.001,nan\n", nullptr, "/s.csv:3:7: ", "not a finite number"},
      {"infinite time", "t_s,setpoint_deg\n0,30\ninf,30\n", nullptr, "/s.csv:3:1: ", "not a finite"},
      {"short row", "t_s,setpoint_deg\n0,30\n0.001\n", nullptr, "/s.csv:3:6: ",
       "missing column 'setpoint_deg'"},
      {"empty cell", "t_s,setpoint_deg\n0,30\n0.001,\n", nullptr, "/s.csv:3:7: ", "empty cell"},
      {"header only", "t_s,setpoint_deg\n", nullptr, "/s.csv:1:1: ", "no rows"},
      {"empty file", "", nullptr, "/s.csv:1:1: ", "empty file"},
      {"unknown bench key", nullptr, "servo:\n  Kp: 12\n  Kq: 3\n", "/b.yaml:3:3: ", "'Kq'"},
      {"unknown top key", nullptr, "servos:\n  Kp: 12\n", "/b.yaml:1:1: ", "'servos'"},
      {"bench value not a number", nullptr, "load:\n  inertia_kgm2: abc\n", "/b.yaml:2:17: ",
       "'load.inertia_kgm2'"},
      {"bench value out of range", nullptr, "servo:\n  R: 0\n", "/b.yaml:2:6: ", "'servo.R'"},
      {"bench NaN", nullptr, "load: {torque_nm: .nan}\n", "/b.yaml:1:19: ", "'load.torque_nm'"},
      {"dt not an integer", nullptr, "sim:\n  dt_us: 12.5\n", "/b.yaml:2:10: ", "'sim.dt_us'"},
      {"nothing turns", nullptr, "servo: {J: 0}\nload: {inertia_kgm2: 0}\n", "/b.yaml:2:7: ",
       "must be > 0"},
      {"yaml syntax", nullptr, "servo: [1, 2\n", "/b.yaml:", "YAML syntax error"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    TempDir dir;
    const std::string csv = c.csv ? dir.write("s.csv", c.csv) : kScenes + "step-30-120.csv";
    std::vector<std::string> args = {"--setpoints", csv, "--out", dir.file("o.csv")};
    if (c.yaml) {
      args.push_back("--bench");
      args.push_back(dir.write("b.yaml", c.yaml));
    }
    const Result r = bench(dir, args);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expect2), std::string::npos) << r.err;
    EXPECT_NE(access(dir.file("o.csv").c_str(), F_OK), 0) << "no output on error";
  }
  TempDir dir;
  Result r = bench(dir, {"--setpoints", dir.file("missing.csv"), "--out", dir.file("o.csv")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing.csv: cannot open"), std::string::npos) << r.err;
  r = bench(dir, {"--bench", dir.file("missing.yaml"), "--setpoints", kScenes + "step-30-120.csv",
                  "--out", dir.file("o.csv")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing.yaml: cannot open"), std::string::npos) << r.err;
  r = bench(dir, {"--setpoints", kScenes + "step-30-120.csv", "--out", dir.file("no/such/dir.csv")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot write"), std::string::npos) << r.err;
}

}  // namespace
