// The servo model alone, on a rigid load on a fixed base, against a fine RK4
// reference of the continuous equations (servo_model.h): stability at the
// 0.5 ms step, convergence as the step shrinks, the ADC scale, limp mode.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "model/units.h"
#include "physics/actuators/servo_model.h"

namespace chainsim {
namespace {

struct Traj {
  std::vector<double> t, theta, current;
};

// the continuous model, RK4 with a 1 us step, sampled every `sample_s`
Traj reference(const ServoParams& p, double load_inertia, double theta0, double setpoint,
               double duration, double sample_s) {
  const double inertia = load_inertia + p.j;
  double th = theta0, w = 0, i = 0;
  auto deriv = [&](double th_, double w_, double i_, double* dth, double* dw, double* di) {
    const double ea = std::clamp(p.kp * (setpoint - th_), -p.supply_v, p.supply_v);
    *dth = w_;
    // static-friction dead zone (ServoParams::i_threshold_a; 0 = off)
    const double th = p.i_threshold_a;
    const double i_eff = i_ > th ? i_ - th : (i_ < -th ? i_ + th : 0.0);
    *dw = (p.kt * i_eff - p.b * w_) / inertia;
    *di = (ea - p.r * i_ - p.km * w_) / p.l;
  };
  const double h = 1e-6;
  const int every = static_cast<int>(std::lround(sample_s / h));
  const int n = static_cast<int>(std::lround(duration / h));
  Traj out;
  for (int k = 0; k <= n; ++k) {
    if (k % every == 0) {
      out.t.push_back(k * h);
      out.theta.push_back(th);
      out.current.push_back(i);
    }
    double a[3], b[3], c[3], d[3];
    deriv(th, w, i, &a[0], &a[1], &a[2]);
    deriv(th + h / 2 * a[0], w + h / 2 * a[1], i + h / 2 * a[2], &b[0], &b[1], &b[2]);
    deriv(th + h / 2 * b[0], w + h / 2 * b[1], i + h / 2 * b[2], &c[0], &c[1], &c[2]);
    deriv(th + h * c[0], w + h * c[1], i + h * c[2], &d[0], &d[1], &d[2]);
    th += h / 6 * (a[0] + 2 * b[0] + 2 * c[0] + d[0]);
    w += h / 6 * (a[1] + 2 * b[1] + 2 * c[1] + d[1]);
    i += h / 6 * (a[2] + 2 * b[2] + 2 * c[2] + d[2]);
  }
  return out;
}

// the model as the World uses it: the step law solved implicitly with the load
// (what ODE's motor row does for one body on a fixed hinge), then
// semi-implicit Euler for the angle (as ODE)
Traj discrete(const ServoParams& p, double load_inertia, double theta0, double setpoint,
              double duration, double h, double sample_s) {
  ServoModel s(p);
  s.set_setpoint(setpoint);
  double th = theta0, w = 0;
  const int every = static_cast<int>(std::lround(sample_s / h));
  const int n = static_cast<int>(std::lround(duration / h));
  Traj out;
  for (int k = 0; k <= n; ++k) {
    if (k % every == 0) {
      out.t.push_back(k * h);
      out.theta.push_back(th);
      out.current.push_back(s.current_a());
    }
    const ServoModel::StepLaw law = s.begin_step(th, w, h);
    w = (load_inertia * w / h + law.damping * law.target_rate) / (load_inertia / h + law.damping);
    th += h * w;
    s.end_step(w);
  }
  return out;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) m = std::max(m, std::fabs(a[k] - b[k]));
  return m;
}
double max_of(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

// about the rotation module's capsule + back connector about the pitch axis
constexpr double kLoad = 2.5e-6;

TEST(ServoModel, StepMatchesContinuousReferenceAndConverges) {
  const ServoParams p;
  const double th0 = -60 * kRadPerDeg, sp = 30 * kRadPerDeg, dur = 0.2, sample = 0.002;
  const Traj ref = reference(p, kLoad, th0, sp, dur, sample);
  double prev_err = 1e9;
  for (double h : {0.002, 0.001, 0.0005, 0.00025}) {
    const Traj d = discrete(p, kLoad, th0, sp, dur, h, sample);
    const double err = max_abs_diff(ref.theta, d.theta);
    const double ierr = max_abs_diff(ref.current, d.current);
    RecordProperty("theta_err_deg_h" + std::to_string(static_cast<int>(h * 1e6)), err / kRadPerDeg);
    std::printf("h=%6.0f us: max angle error %.3f deg, max current error %.4f A\n", h * 1e6,
                err / kRadPerDeg, ierr);
    EXPECT_LT(err, prev_err * 0.8) << "error must shrink with the step";
    prev_err = err;
    if (h == 0.0005) {
      EXPECT_LT(err, 2.0 * kRadPerDeg);
      EXPECT_LT(ierr, 0.05);
    }
  }
  // both settle at the set-point without overshoot worth mentioning
  EXPECT_NEAR(ref.theta.back(), sp, 0.5 * kRadPerDeg);
  EXPECT_LT(max_of(ref.theta), sp + 2 * kRadPerDeg);
}

TEST(ServoModel, StableWithoutLoadAndWithHeavyLoad) {
  const ServoParams p;
  for (double load : {0.0, 1e-8, kLoad}) {
    const Traj d = discrete(p, load, 0.0, 45 * kRadPerDeg, 0.5, 0.0005, 0.0005);
    for (double th : d.theta) ASSERT_TRUE(std::isfinite(th));
    // the last 10% of the run: settled, no oscillation
    const size_t from = d.theta.size() * 9 / 10;
    double lo = 1e9, hi = -1e9;
    for (size_t k = from; k < d.theta.size(); ++k) {
      lo = std::min(lo, d.theta[k]);
      hi = std::max(hi, d.theta[k]);
    }
    EXPECT_LT((hi - lo) / kRadPerDeg, 0.05) << "load " << load;
    EXPECT_NEAR(d.theta.back(), 45 * kRadPerDeg, 0.5 * kRadPerDeg) << "load " << load;
  }
  // 400 times the module's own load (about a 40 cm chain swung about the
  // axis): lightly damped (zeta ~ 0.07), it rings for seconds, as the
  // continuous model does; the discrete one follows it
  const double heavy = 1e-3;
  const Traj ref = reference(p, heavy, 0.0, 45 * kRadPerDeg, 3.0, 0.01);
  const Traj d = discrete(p, heavy, 0.0, 45 * kRadPerDeg, 3.0, 0.0005, 0.01);
  const double err = max_abs_diff(ref.theta, d.theta);
  std::printf("heavy load: max angle error %.3f deg over 3 s\n", err / kRadPerDeg);
  EXPECT_LT(err, 1.0 * kRadPerDeg);
}

// the paper's static-friction threshold: no torque while |i| <= I_th
TEST(ServoModel, CurrentThresholdDeadZone) {
  ServoParams p;
  p.i_threshold_a = 0.05;
  // a 2 degree error drives Kp 2deg / R = 0.035 A < 0.05 A: the current flows
  // (and is measured) but the motor does not move
  const Traj small = discrete(p, kLoad, 0.0, 2 * kRadPerDeg, 0.2, 0.0005, 0.0005);
  for (double th : small.theta) ASSERT_EQ(th, 0.0);
  EXPECT_NEAR(small.current.back(), p.kp * 2 * kRadPerDeg / p.r, 1e-6);
  // the 90 degree move: the discrete model follows the continuous one with
  // the dead zone, stops within the band I_th R / Kp of the set-point and
  // stays there
  const double th0 = -60 * kRadPerDeg, sp = 30 * kRadPerDeg, band = p.i_threshold_a * p.r / p.kp;
  const Traj ref = reference(p, kLoad, th0, sp, 0.3, 0.002);
  const Traj d = discrete(p, kLoad, th0, sp, 0.3, 0.0005, 0.002);
  const double err = max_abs_diff(ref.theta, d.theta);
  std::printf("threshold 0.05 A: max angle error %.3f deg, final %.3f deg (ref %.3f, band %.2f)\n",
              err / kRadPerDeg, d.theta.back() / kRadPerDeg, ref.theta.back() / kRadPerDeg, band / kRadPerDeg);
  EXPECT_LT(err, 2.0 * kRadPerDeg);
  EXPECT_LE(std::fabs(d.theta.back() - sp), band + 0.01 * kRadPerDeg);
  EXPECT_GT(std::fabs(d.theta.back() - sp), 0.1 * kRadPerDeg);   // the dead zone shows
  const size_t from = d.theta.size() * 2 / 3;
  for (size_t k = from; k < d.theta.size(); ++k) EXPECT_NEAR(d.theta[k], d.theta.back(), 1e-4 * kRadPerDeg);
  // the torque reported is Kt dz(i)
  ServoModel s(p);
  s.set_setpoint(1.0);
  for (int k = 0; k < 200; ++k) {
    s.begin_step(0.0, 0.0, 0.0005);
    s.end_step(0.0);
  }
  EXPECT_NEAR(s.motor_torque_nm(), p.kt * (p.supply_v / p.r - p.i_threshold_a), 1e-9);
}

TEST(ServoModel, StallCurrentAndAdcScale) {
  ServoParams p;
  ServoModel s(p);
  s.set_setpoint(1.0);   // far from 0: ea saturates at Vs
  for (int k = 0; k < 200; ++k) {  // 100 ms held still (stalled)
    s.begin_step(0.0, 0.0, 0.0005);
    s.end_step(0.0);
  }
  EXPECT_NEAR(s.current_a(), p.supply_v / p.r, 1e-6);
  EXPECT_NEAR(s.filtered_current_a(), p.supply_v / p.r, 1e-6);
  // 0.4167 A / 0.5 A * 1023 = 852.5 -> 853
  EXPECT_NEAR(s.adc_counts(), 852.5, 0.6);
  EXPECT_NEAR(s.motor_torque_nm(), p.kt * p.supply_v / p.r, 1e-6);
}

TEST(ServoModel, DisabledIsLimpAndCurrentDecays) {
  ServoParams p;
  ServoModel s(p);
  s.set_setpoint(1.0);
  for (int k = 0; k < 40; ++k) {
    s.begin_step(0.0, 0.0, 0.0005);
    s.end_step(0.0);
  }
  ASSERT_GT(s.current_a(), 0.3);
  s.set_enabled(false);
  for (int k = 0; k < 20; ++k) {  // 10 ms = 16 L/R time constants
    const ServoModel::StepLaw law = s.begin_step(0.0, 2.0, 0.0005);
    EXPECT_GT(law.damping, 0);
    s.end_step(2.0);  // turning: no back-EMF current either (open circuit)
  }
  EXPECT_LT(std::fabs(s.current_a()), 1e-4);
  const ServoModel::StepLaw law = s.begin_step(0.0, 2.0, 0.0005);
  // only friction and the rotor inertia are left: tau = D (v - w') with
  // D v = J w / h, i.e. no drive torque
  EXPECT_NEAR(law.damping * law.target_rate, p.j / 0.0005 * 2.0, 1e-6);
  EXPECT_NEAR(law.damping, p.b + p.j / 0.0005, 1e-12);
}

}  // namespace
}  // namespace chainsim
