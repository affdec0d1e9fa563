// The servo test stand (servo_stand.h).
//
// The stand is an ODE world of its own: a rotor body on a hinge to the static
// environment (the fixed base), no gravity, the rotor's moment of inertia
// about the axis = the bench's load inertia. The servo is the robot's
// ServoModel (servo_model.h) coupled exactly as the World couples it: a
// one-axis angular motor on the hinge with dParamVel / dParamCFM from the
// model's step law (an implicit damper; see servo_model.h), through the same
// drive_servo_motor as the World's rotary servos (physics/actuators/). The constant
// external torque is added to the hinge every step. The stand steps with
// dWorldStep (ODE's exact LCP solver; one body, so it costs nothing) rather
// than the robot's QuickStep, whose unconverged iterations would only add
// solver noise to a bench meant for comparing with the continuous model.
//
// Angles: the bench angle is the hinge angle in degrees, continuous (no stops,
// no wrap at +-180), so the paper's 30 -> 120 degree test is written as is.
#include "analysis/servo_bench/servo_stand.h"
#include "model/units.h"
#include "physics/actuators/rotary_servo.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>

namespace chainsim {
namespace {

constexpr double kEpsUs = 1e-3;            // time tolerance, microseconds

struct Row {
  double t_s = 0;
  double setpoint_deg = 0;
};

ServoParams with_pulse_origin(ServoParams p, double sp0_deg) {
  if (p.pwm_pulse_s_per_deg > 0.0) p.pwm_pulse_origin_deg = sp0_deg;
  return p;
}

class Stand {
 public:
  // sp0_deg: the first row's set-point, the stand's angle 0 (a servo that
  // decodes pulses at their falling edge needs the absolute set-point)
  Stand(const BenchConfig& b, BenchSolver solver, double sp0_deg)
      : cfg_(b), model_(with_pulse_origin(b.servo, sp0_deg)), h_(b.dt_us * 1e-6), solver_(solver) {
    jl_ = std::max(b.load_inertia_kgm2, 1e-12);
    jh_ = jl_ / h_;
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
    dMass m;
    dMassSetParameters(&m, 0.01, 0, 0, 0, jl_, jl_, jl_, 0, 0, 0);
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
    dJointSetAMotorParam(motor_, dParamFMax, kServoMotorFMax);
  }
  ~Stand() {
    if (world_) dWorldDestroy(world_);
  }
  Stand(const Stand&) = delete;
  Stand& operator=(const Stand&) = delete;

  // model angles are relative to the start (the hinge's 0); the bench adds
  // the first set-point back
  void set_setpoint_rad(double rel) { model_.set_setpoint(rel); }

  // (inline: the closed form's steps of two stands side by side overlap)
  [[gnu::always_inline]] void step() {
    if (solver_ == BenchSolver::closed_form) {
      // one degree of freedom: (Jl/h + D) w' = Jl w/h + D v + tau_load, then
      // theta += h w' (ODE's semi-implicit position update)
      const ServoModel::StepLaw law = model_.begin_step(theta_, w_, h_);
      const double jh = jh_;
      w_ = (jh * w_ + law.torque0 + cfg_.load_torque_nm) / (jh + law.damping);
      model_.end_step(w_);
      theta_ += h_ * w_;
      return;
    }
    step_ode();
  }

 private:
  void step_ode() {
    const double w = dJointGetHingeAngleRate(hinge_);
    drive_servo_motor(motor_, model_.begin_step(theta_, w, h_));
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

 public:
  double theta_rad() const { return theta_; }
  double filtered_current_a() const { return model_.filtered_current_a(); }

 private:
  BenchConfig cfg_;
  ServoModel model_;
  double h_;
  BenchSolver solver_;
  double jl_ = 0, w_ = 0;   // load inertia; closed form: hinge rate
  double jh_ = 0;           // closed form: jl_ / h_
  dWorldID world_ = nullptr;
  dBodyID rotor_ = nullptr;
  dJointID hinge_ = nullptr, motor_ = nullptr;
  double theta_ = 0, last_raw_ = 0;
};

// a stand's state after a step, converted to a sample only where one is
// written (the calibration's optimiser runs this some thousand times)
struct Raw {
  double theta_rad, current_a;
};
Raw raw(const Stand& s) { return Raw{s.theta_rad(), s.filtered_current_a()}; }

// one stand's run: its rows, the samples so far, its last two step ends
struct Lane {
  Stand* stand;
  size_t count;
  std::vector<BenchSample>* out;
  Raw prev, cur;
};

// the rows shared by the lanes, and where their stepping stands
struct RowClock {
  const std::vector<Row>& rows;
  std::vector<double> rel;   // the rows' times from the first, us
  double sp0, dt;
  int64_t n = 0;        // steps done: the state is that of time n dt
  size_t active = 0;    // the row whose set-point is applied
  BenchSample sample(const Raw& r) const { return BenchSample{sp0 + r.theta_rad / kDeg, r.current_a}; }
  static constexpr double kDeg = kPi / 180.0;
};

// rows [k0, k1) for the first `lanes` lanes (N of them when N > 0: the
// compiler then lays the lanes' steps side by side, which is where two
// independent stands overlap on one core; each stand's steps are the same
// operations in the same order as alone, so its samples are the same bytes)
template <size_t N>
void advance(Lane* lane, size_t lanes, RowClock& c, size_t k0, size_t k1) {
  const size_t m = N > 0 ? N : lanes;
  for (size_t k = k0; k < k1; ++k) {
    const double tk = c.rel[k];
    while (static_cast<double>(c.n) * c.dt < tk - kEpsUs) {
      // set-point of step n: the last row at or before its start
      while (c.active + 1 < c.rel.size() && c.rel[c.active + 1] <= static_cast<double>(c.n) * c.dt + kEpsUs)
        ++c.active;
      const double sp = (c.rows[c.active].setpoint_deg - c.sp0) * RowClock::kDeg;
      for (size_t i = 0; i < m; ++i) {
        Lane& l = lane[i];
        l.stand->set_setpoint_rad(sp);
        l.stand->step();
        l.prev = l.cur;
        l.cur = raw(*l.stand);
      }
      ++c.n;
    }
    // (n-1) dt < tk <= n dt: linear between the two step ends
    const double tn = static_cast<double>(c.n) * c.dt;
    const bool on_step = c.n == 0 || std::fabs(tn - tk) <= kEpsUs;
    const double f = (tk - (tn - c.dt)) / c.dt;
    for (size_t i = 0; i < m; ++i) {
      const Lane& l = lane[i];
      if (on_step) {
        l.out->push_back(c.sample(l.cur));
      } else {
        const BenchSample a = c.sample(l.prev), b = c.sample(l.cur);
        l.out->push_back({a.angle_deg + f * (b.angle_deg - a.angle_deg), a.current_a + f * (b.current_a - a.current_a)});
      }
    }
  }
}

// the stands' responses to the same rows, stepped side by side: stand i
// gives the first counts[i] rows (at least one)
std::vector<std::vector<BenchSample>> run_stands(const std::vector<const BenchConfig*>& b, const std::vector<Row>& rows,
                                                 const std::vector<size_t>& counts, BenchSolver solver) {
  const size_t lanes = b.size();
  std::vector<std::unique_ptr<Stand>> stand(lanes);
  for (size_t i = 0; i < lanes; ++i) stand[i] = std::make_unique<Stand>(*b[i], solver, rows.front().setpoint_deg);
  const size_t count = *std::max_element(counts.begin(), counts.end());
  RowClock c{rows, std::vector<double>(count), rows.front().setpoint_deg, static_cast<double>(b[0]->dt_us)};
  for (size_t k = 0; k < count; ++k) c.rel[k] = (rows[k].t_s - rows.front().t_s) * 1e6;
  std::vector<std::vector<BenchSample>> out(lanes);
  std::vector<Lane> lane(lanes);
  for (size_t i = 0; i < lanes; ++i) {
    lane[i] = {stand[i].get(), counts[i], &out[i], raw(*stand[i]), raw(*stand[i])};
    out[i].reserve(counts[i]);
    out[i].push_back(c.sample(lane[i].cur));
  }
  // the longest first: the lanes that still need rows are a prefix
  std::stable_sort(lane.begin(), lane.end(), [](const Lane& x, const Lane& y) { return x.count > y.count; });
  for (size_t k = 1, live = lanes; k < count;) {
    while (lane[live - 1].count <= k) --live;
    const size_t until = lane[live - 1].count;   // the rows every live lane needs
    if (live == 1)
      advance<1>(lane.data(), live, c, k, until);
    else if (live == 2)
      advance<2>(lane.data(), live, c, k, until);
    else
      advance<0>(lane.data(), live, c, k, until);
    k = until;
  }
  return out;
}

}  // namespace

std::vector<BenchSample> simulate_bench(const BenchConfig& b, const std::vector<double>& t_s,
                                        const std::vector<double>& setpoint_deg, BenchSolver solver,
                                        size_t count) {
  return std::move(simulate_benches({&b}, t_s, setpoint_deg, solver, {count}).front());
}

std::vector<std::vector<BenchSample>> simulate_benches(const std::vector<const BenchConfig*>& b,
                                                       const std::vector<double>& t_s,
                                                       const std::vector<double>& setpoint_deg, BenchSolver solver,
                                                       const std::vector<size_t>& counts) {
  if (t_s.empty() || t_s.size() != setpoint_deg.size())
    throw std::invalid_argument("simulate_bench: t_s and setpoint_deg must be non-empty, same length");
  if (b.empty() || b.size() != counts.size())
    throw std::invalid_argument("simulate_benches: one count per bench, at least one bench");
  for (const BenchConfig* c : b)
    if (c->dt_us != b.front()->dt_us) throw std::invalid_argument("simulate_benches: the benches' steps differ");
  std::vector<size_t> n(counts.size());
  for (size_t i = 0; i < n.size(); ++i) n[i] = std::clamp<size_t>(counts[i], 1, t_s.size());
  std::vector<Row> rows(*std::max_element(n.begin(), n.end()));
  for (size_t k = 0; k < rows.size(); ++k) rows[k] = {t_s[k], setpoint_deg[k]};
  return run_stands(b, rows, n, solver);
}

}  // namespace chainsim
