#include "testing/motion.h"

#include <cmath>
#include <map>

#include "model/units.h"
#include "output/run_reader.h"

namespace chainsim {
namespace {

constexpr double kStartWindowS = 0.2;
constexpr double kEndWindowS = 1.0;
constexpr double kPathWindowS = 0.5;

// the body prefixes "mK.<body>" of each module (RunReader::body_columns)
std::vector<std::vector<std::string>> bodies_by_module(RunReader& run) {
  const int n = run.body_column_modules();
  if (n == 0) throw MotionError("trace.csv has no body columns (mK.<body>.x)");
  std::vector<std::vector<std::string>> out;
  for (int k = 0; k < n; ++k) {
    if (run.body_columns(k).empty()) throw MotionError("trace.csv: the body columns skip module m" + std::to_string(k));
    out.push_back(run.body_columns(k));
  }
  return out;
}

const std::vector<double>& col(RunReader& run, const std::string& name) {
  const auto* c = run.trace_column(name);
  if (!c) throw MotionError("trace.csv has no column " + name);
  return *c;
}

double window_mean(const std::vector<double>& t, const std::vector<double>& v, double from, double to) {
  double s = 0;
  int k = 0;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= from && t[i] <= to) s += v[i], ++k;
  if (k == 0) throw MotionError("the trace has no rows between " + std::to_string(from) + " and " + std::to_string(to) + " s");
  return s / k;
}

}  // namespace

ChainMotion chain_motion(RunReader& run) {
  const auto& t = run.trace_time();
  const size_t T = t.size();
  if (T < 2) throw MotionError("the trace has fewer than 2 rows");
  const auto mods = bodies_by_module(run);
  const size_t n = mods.size();
  const size_t g = std::max<size_t>(1, n / 4);
  if (n < 2) throw MotionError("the heading needs a chain of at least 2 modules");

  std::vector<double> cx(T, 0), cy(T, 0), cz(T, 0), hd(T, 0);
  size_t nbodies = 0;
  for (const auto& m : mods) nbodies += m.size();
  std::vector<double> hx(T, 0), hy(T, 0), tx(T, 0), ty(T, 0);
  for (size_t k = 0; k < n; ++k)
    for (const std::string& b : mods[k]) {
      const auto& x = col(run, b + ".x");
      const auto& y = col(run, b + ".y");
      const auto& z = col(run, b + ".z");
      for (size_t i = 0; i < T; ++i) {
        cx[i] += x[i] / nbodies;
        cy[i] += y[i] / nbodies;
        cz[i] += z[i] / nbodies;
        if (k < g) hx[i] += x[i], hy[i] += y[i];
        if (k >= n - g) tx[i] += x[i], ty[i] += y[i];
      }
    }
  for (size_t i = 0; i < T; ++i) {
    double a = std::atan2(hy[i] - ty[i], hx[i] - tx[i]);
    if (i > 0) {
      while (a - hd[i - 1] > kPi) a -= 2 * kPi;
      while (a - hd[i - 1] < -kPi) a += 2 * kPi;
    }
    hd[i] = a;
  }
  const double t0 = t.front(), end = t.back();
  auto change = [&](const std::vector<double>& v) {
    return window_mean(t, v, end - kEndWindowS, end) - window_mean(t, v, t0, t0 + kStartWindowS);
  };
  ChainMotion r;
  r.dx_m = change(cx);
  r.dy_m = change(cy);
  r.dz_m = change(cz);
  r.distance_m = std::hypot(r.dx_m, r.dy_m);
  r.heading_deg = change(hd) * kDegPerRad;
  size_t w0 = 0;
  for (size_t i = 1; i < T; ++i) {
    if (t[i] - t[w0] < kPathWindowS && i + 1 < T) continue;
    const double ux = std::cos(hd[w0]), uy = std::sin(hd[w0]);
    const double ddx = cx[i] - cx[w0], ddy = cy[i] - cy[w0];
    r.axial_m += ddx * ux + ddy * uy;
    r.lateral_m += -ddx * uy + ddy * ux;
    w0 = i;
  }
  return r;
}

// q_prev^-1 q_cur is each row's rotation in the body frame; its part about
// the local z axis is 2 atan2(z, w)
static double twist_deg(RunReader& run, const std::string& body) {
  const auto& qw = col(run, body + ".qw");
  const auto& qx = col(run, body + ".qx");
  const auto& qy = col(run, body + ".qy");
  const auto& qz = col(run, body + ".qz");
  double sum = 0;
  for (size_t i = 1; i < qw.size(); ++i) {
    const double w1 = qw[i - 1], x1 = -qx[i - 1], y1 = -qy[i - 1], z1 = -qz[i - 1];
    const double w2 = qw[i], x2 = qx[i], y2 = qy[i], z2 = qz[i];
    double w = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2;
    double z = w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2;
    if (w < 0) w = -w, z = -z;
    sum += 2 * std::atan2(z, w) * kDegPerRad;
  }
  return sum;
}

const std::vector<std::string>& motion_metric_names() {
  static const std::vector<std::string> names = {"dx_m",      "dy_m",    "dz_m",      "distance_m",
                                                 "heading_deg", "axial_m", "lateral_m", "mK.<body>.twist_deg"};
  return names;
}

double motion_metric(RunReader& run, const std::string& name) {
  static const std::string kTwist = ".twist_deg";
  if (name.size() > kTwist.size() && name.ends_with(kTwist)) {
    const std::string body = name.substr(0, name.size() - kTwist.size());
    if (!run.trace_column(body + ".qw")) {
      std::string known;
      for (const auto& m : bodies_by_module(run))
        for (const auto& b : m) known += (known.empty() ? "" : ", ") + b;
      throw MotionError("no body '" + body + "' in trace.csv (bodies: " + known + ")", true);
    }
    return twist_deg(run, body);
  }
  static const std::map<std::string, double ChainMotion::*> fields = {
      {"dx_m", &ChainMotion::dx_m},           {"dy_m", &ChainMotion::dy_m},
      {"dz_m", &ChainMotion::dz_m},           {"distance_m", &ChainMotion::distance_m},
      {"heading_deg", &ChainMotion::heading_deg}, {"axial_m", &ChainMotion::axial_m},
      {"lateral_m", &ChainMotion::lateral_m}};
  const auto it = fields.find(name);
  if (it == fields.end()) {
    std::string known;
    for (const auto& n : motion_metric_names()) known += (known.empty() ? "" : ", ") + n;
    throw MotionError("unknown motion metric 'motion." + name + "' (known: " + known + ")", true);
  }
  return chain_motion(run).*(it->second);
}

}  // namespace chainsim
