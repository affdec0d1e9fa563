// The servo model's step (servo_model.h), defined inline: the servo test
// stand steps it some ten million times a second in the calibration, and
// there two models' steps inlined side by side overlap on one core
// (servo_stand.cpp); the World calls the same code.
#pragma once

#include <algorithm>
#include <climits>
#include <cmath>

#include "model/units.h"
#include "physics/actuators/fast_tanh.h"
#include "physics/actuators/servo_model.h"

namespace chainsim {

// the drive voltage the amplifier applies for a set-point (rad) at the
// output angle theta and rotor rate wr, with the catalogue's drive effects
[[gnu::always_inline]] inline double ServoModel::drive_voltage(double setpoint, double theta, double wr) const {
  double err = setpoint - theta;
  if (p_.deadband_deg > 0.0) {  // deadband: errors within +-width/2 are ignored
    const double half = deg_to_rad(0.5 * p_.deadband_deg);
    err = std::fabs(err) <= half ? 0.0 : err - std::copysign(half, err);
  }
  // deadband, comparator form: no drive inside the window, the whole error
  // outside it
  if (p_.deadband_comparator_deg > 0.0 && std::fabs(err) <= deg_to_rad(0.5 * p_.deadband_comparator_deg)) err = 0.0;
  double ea = std::clamp(p_.kp * err, -p_.supply_v, p_.supply_v);
  if (p_.supply_sag_ohm > 0.0 && p_.supply_v > 0.0) {  // supply_sag: duty x (Vs - Rs |i|), or duty x V
    if (rail_rs_ > 0.0)
      ea *= std::max(0.0, rail_v_) / p_.supply_v;
    else
      ea *= std::max(0.0, 1.0 - p_.supply_sag_ohm * std::fabs(i_) / p_.supply_v);
  }
  if (p_.supply_sag_linear_ohm > 0.0) {  // supply_sag, linear driver: the limit drops, the gain stays
    const double lim = rail_rs_ > 0.0 ? std::max(0.0, rail_v_)
                                      : std::max(0.0, p_.supply_v - p_.supply_sag_linear_ohm * std::fabs(i_));
    ea = std::clamp(ea, -lim, lim);
  }
  if (p_.current_limit_a > 0.0) {  // current_limit: |ea - Km w| <= R I_lim
    const double lim = p_.r * p_.current_limit_a;
    ea = std::clamp(ea, p_.km * wr - lim, p_.km * wr + lim);
  }
  return ea;
}

[[gnu::always_inline]] inline ServoModel::StepLaw ServoModel::begin_step(double theta, double w, double h) {
  if (h != h_) update_constants(h);
  drive_ = enabled_;
  // pwm_frame_delay: the set-point is latched at the pulse frames only, the
  // first at the phase (before it k < 0: the set-point held from before).
  // sp_before drives the step until a frame inside it, sp_after for the
  // fraction `after` of the step that follows
  double sp_before = setpoint_, sp_after = setpoint_, after = 1.0;
  if (p_.pwm_frame_s > 0.0 && p_.pwm_pulse_s_per_deg > 0.0) {
    // falling edge: the events of the step in time order; a frame (pulse
    // start) takes the set-point of that moment, its falling edge latches it
    // (the width is below the period, so at most one pulse is under way). A
    // latch inside the step drives the part of the step after it
    const double eps = 1e-9 * p_.pwm_frame_s;
    const double end = time_s_ + h - eps;
    sp_before = sp_after = applied_;
    for (;;) {
      const double edge = p_.pwm_frame_phase_s + static_cast<double>(frame_ + 1) * p_.pwm_frame_s;
      if (latch_s_ >= 0.0 && latch_s_ < end && latch_s_ <= edge) {
        if (latch_s_ <= time_s_ + eps) {
          sp_before = pending_;
          after = 1.0;
        } else {
          after = (time_s_ + h - latch_s_) / h;
        }
        sp_after = pending_;
        applied_ = pending_;
        latch_s_ = -1.0;
      } else if (edge < end) {
        ++frame_;
        pending_ = setpoint_;
        const double width =
            rc_pulse_width_s(p_.pwm_pulse_s_per_deg, setpoint_ * kDegPerRad + p_.pwm_pulse_origin_deg);
        latch_s_ = edge + std::clamp(width, 0.0, 0.9 * p_.pwm_frame_s);
      } else {
        break;
      }
    }
  } else if (p_.pwm_frame_s > 0.0) {
    const double eps = 1e-9 * p_.pwm_frame_s;
    // floor, without the library call: truncate, one down for a negative
    // fraction (the same integer as std::floor)
    const double q = (time_s_ - p_.pwm_frame_phase_s) / p_.pwm_frame_s + 1e-9;
    long long k = static_cast<long long>(q);
    if (static_cast<double>(k) > q && k > LLONG_MIN) --k;
    if (k > frame_) {
      frame_ = k;
      applied_ = setpoint_;
    }
    sp_before = sp_after = applied_;
    // a frame inside the step latches the set-point there: the drive is the
    // old set-point's before it and the new one's after it, averaged over the
    // step (latched at the next step instead, a frame came up to one step
    // late, a jitter a calibration at 0.1 deg of noise took for another effect)
    const double next = p_.pwm_frame_phase_s + static_cast<double>(frame_ + 1) * p_.pwm_frame_s;
    if (next > time_s_ + eps && next < time_s_ + h - eps) {
      after = (time_s_ + h - next) / h;
      sp_after = setpoint_;
      ++frame_;
      applied_ = setpoint_;
    }
  } else {
    applied_ = setpoint_;
  }
  time_s_ += h;
  const bool backlash = p_.backlash_deg > 0.0 && p_.j > 0.0;
  // compliant mesh: the rotor always has its own state (below)
  const bool mesh = backlash && p_.backlash_stiffness_nm_rad > 0.0;
  if (!backlash) engaged_ = true;
  // backlash: the step after the gap closed is the (plastic) impact: the rotor
  // still has its own rate wm_ and its momentum J wm_ joins the joint's (rather
  // than being lost); the gap does not reopen within that step
  const bool impact = closed_;
  closed_ = false;
  // the rotor's rate now: the joint's, or its own while it crosses the gap
  // and in the impact step
  const double wr = engaged_ && !impact && !mesh ? w : wm_;
  const double w_rotor = impact ? wm_ : w;
  // rotor inertia, implicit on the joint rate: -J (w' - w)/h
  const double jh = jh_;
  // step-average current = i0 - ci w' (affine in the end-of-step rate w')
  double i0, ci;
  if (drive_) {
    ea_ = drive_voltage(sp_after, theta, wr);
    if (after < 1.0) ea_ = after * ea_ + (1.0 - after) * drive_voltage(sp_before, theta, wr);
    i0 = ea_ * drive_gain_ + phi_ * i_;
    ci = ci_;
  } else {
    ea_ = 0.0;
    i0 = phi_ * i_;   // free-wheeling current, no back-EMF path
    ci = 0.0;
  }
  if (p_.i_threshold_a > 0.0) {
    // static friction: torque Kt dz(i_avg); the branch of dz from the
    // prediction w' = w, then affine (implicit) within it
    const double i_pred = i0 - ci * wr;
    if (i_pred > p_.i_threshold_a) {
      i0 -= p_.i_threshold_a;
    } else if (i_pred < -p_.i_threshold_a) {
      i0 += p_.i_threshold_a;
    } else {
      i0 = 0.0;
      ci = 0.0;
    }
  }
  // coulomb_friction on the output: -Tc tanh(w'/ws) ~ tc0 - dc w'
  double tc0 = 0.0, dc = 0.0;
  if (p_.coulomb_nm > 0.0) {
    // (times the rate's inverse: two divisions fewer on the step's chain)
    constexpr double kInvRate = 1.0 / kCoulombRate;
    const double th = fast_tanh(w * kInvRate);
    dc = p_.coulomb_nm * (1.0 - th * th) * kInvRate;
    tc0 = -p_.coulomb_nm * th + dc * w;
  }
  gap_step_ = false;
  mesh_step_ = false;
  if (mesh) {
    // rotor: (J/h + B + Kt ci) wm' = J wm / h + Kt i0 - tc, and in contact the
    // mesh torque tc = k (pen + h (wm' - w')) + c (wm' - w'): both affine in
    // w' once wm' is eliminated; contact from the rotor's free prediction,
    // kept only if it pushes (no tension) at w' = w
    const double g = deg_to_rad(0.5 * p_.backlash_deg);
    const double k = p_.backlash_stiffness_nm_rad;
    const double k2 = k * h + 2.0 * std::sqrt(k * p_.j);
    const double a = jh + p_.b + p_.kt * ci, m = jh * wm_ + p_.kt * i0;
    mesh_step_ = true;
    mesh_a_ = a, mesh_m_ = m, mesh_kp_ = 0.0, mesh_k2_ = 0.0;
    const double d_free = delta_ + h * (m / a - w);
    if (std::fabs(d_free) > g) {
      const double pen = delta_ - std::copysign(g, d_free);
      const double t0 = (k * pen * a + k2 * m) / (a + k2), dm = k2 * a / (a + k2);
      if ((t0 - dm * w) * d_free > 0.0) {
        mesh_a_ = a + k2, mesh_kp_ = k * pen, mesh_k2_ = k2;
        return StepLaw::of(t0 + tc0, dm + dc);
      }
    }
    return StepLaw::of(tc0, dc + 1e-9);
  }
  if (backlash) {
    const double g = deg_to_rad(0.5 * p_.backlash_deg);
    const double tq = i0 - ci * wr;  // sign of the motor torque about to act
    if (engaged_ && !impact && tq * delta_ < 0.0) {  // pulls away from the contact side: the gap opens
      engaged_ = false;
      wm_ = w;
    }
    if (!engaged_) {
      // the rotor alone: J (wm' - wm)/h = Kt (i0 - ci wm') - B wm'
      gap_step_ = true;
      const double wm_next = (jh * wm_ + p_.kt * i0) / (jh + p_.b + p_.kt * ci);
      delta_ += (wm_next - w) * h;
      wm_ = wm_next;
      if (std::fabs(delta_) >= g) {  // the gap closes (inelastic)
        delta_ = std::copysign(g, delta_);
        engaged_ = true;
        closed_ = true;
      }
      return StepLaw::of(tc0, dc + 1e-9);
    }
  }
  // step-average electromagnetic torque = t0 - c_emf w'
  const double t0 = p_.kt * i0, c_emf = p_.kt * ci;
  return StepLaw::of(t0 + tc0 + jh * w_rotor, c_emf + p_.b + jh + dc);
}

[[gnu::always_inline]] inline void ServoModel::end_step(double w_next) {
  if (mesh_step_) {  // compliant backlash: the rotor's own rate, from w'
    const double wm_next = (mesh_m_ - mesh_kp_ + mesh_k2_ * w_next) / mesh_a_;
    delta_ += (wm_next - w_next) * h_;
    wm_ = wm_next;
  }
  const double wr = gap_step_ || mesh_step_ ? wm_ : w_next;  // the rotor's rate (back-EMF)
  if (!gap_step_ && !mesh_step_) wm_ = w_next;
  const double i_inf = drive_ ? (ea_ - p_.km * wr) * inv_r_ : 0.0;
  i_mean_ = (1.0 - phi_) * i_inf + phi_ * i_;
  i_ = i_inf + (i_ - i_inf) * e_;
  // RC filter of |i|, exact for the step-average |i| held over the step
  i_f_ = std::fabs(i_mean_) + (i_f_ - std::fabs(i_mean_)) * ef_;
  if (rail_rs_ > 0.0) {  // supply_sag, rail variant: the rail recharges through Rs, the driver draws
    double draw = 0.0;
    if (drive_) draw = p_.supply_sag_ohm > 0.0 ? (rail_v_ > 0.0 ? ea_ / rail_v_ : 0.0) * i_mean_ : std::fabs(i_mean_);
    const double v_inf = p_.supply_v - rail_rs_ * draw;
    rail_v_ = v_inf + (rail_v_ - v_inf) * er_;
  }
}

}  // namespace chainsim
