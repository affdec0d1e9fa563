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
#include "physics/actuators/rotary_servo.h"
#include "physics/units.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace chainsim {
namespace {

constexpr double kEpsUs = 1e-3;            // time tolerance, microseconds

struct Row {
  double t_s = 0;
  double setpoint_deg = 0;
};

class Stand {
 public:
  Stand(const BenchConfig& b, BenchSolver solver)
      : cfg_(b), model_(b.servo), h_(b.dt_us * 1e-6), solver_(solver) {
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

  void step() {
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

std::vector<BenchSample> run_stand(const BenchConfig& b, const std::vector<Row>& rows, BenchSolver solver) {
  Stand stand(b, solver);
  const double deg = kPi / 180.0;
  const double sp0 = rows.front().setpoint_deg;
  const double dt = static_cast<double>(b.dt_us);
  // the rows' times from the first, us
  std::vector<double> rel(rows.size());
  for (size_t k = 0; k < rows.size(); ++k) rel[k] = (rows[k].t_s - rows.front().t_s) * 1e6;
  // the stand's state after a step, converted to a sample only where one is
  // written (the calibration's optimiser runs this some thousand times)
  struct Raw {
    double theta_rad, current_a;
  };
  auto raw = [&] { return Raw{stand.theta_rad(), stand.filtered_current_a()}; };
  auto sample = [&](const Raw& r) { return BenchSample{sp0 + r.theta_rad / deg, r.current_a}; };
  std::vector<BenchSample> out;
  out.reserve(rows.size());
  Raw prev = raw(), cur = prev;
  out.push_back(sample(cur));
  int64_t n = 0;        // steps done: the state is that of time n dt
  size_t active = 0;    // the row whose set-point is applied
  for (size_t k = 1; k < rows.size(); ++k) {
    const double tk = rel[k];
    while (static_cast<double>(n) * dt < tk - kEpsUs) {
      // set-point of step n: the last row at or before its start
      while (active + 1 < rows.size() && rel[active + 1] <= static_cast<double>(n) * dt + kEpsUs) ++active;
      stand.set_setpoint_rad((rows[active].setpoint_deg - sp0) * deg);
      stand.step();
      prev = cur;
      cur = raw();
      ++n;
    }
    // (n-1) dt < tk <= n dt: linear between the two step ends
    const double tn = static_cast<double>(n) * dt;
    if (n == 0 || std::fabs(tn - tk) <= kEpsUs) {
      out.push_back(sample(cur));
    } else {
      const double f = (tk - (tn - dt)) / dt;
      const BenchSample a = sample(prev), c = sample(cur);
      out.push_back({a.angle_deg + f * (c.angle_deg - a.angle_deg), a.current_a + f * (c.current_a - a.current_a)});
    }
  }
  return out;
}

}  // namespace

std::vector<BenchSample> simulate_bench(const BenchConfig& b, const std::vector<double>& t_s,
                                        const std::vector<double>& setpoint_deg, BenchSolver solver,
                                        size_t count) {
  if (t_s.empty() || t_s.size() != setpoint_deg.size())
    throw std::invalid_argument("simulate_bench: t_s and setpoint_deg must be non-empty, same length");
  std::vector<Row> rows(std::clamp<size_t>(count, 1, t_s.size()));
  for (size_t k = 0; k < rows.size(); ++k) rows[k] = {t_s[k], setpoint_deg[k]};
  return run_stand(b, rows, solver);
}

}  // namespace chainsim
