// The hidden-effect cases of the calibration tests and the study: every
// catalogue effect alone, every pair, null data, an effect outside the
// catalogue (generator A, synth.h), and backlash and supply sag from the
// independent generator B (synth_b.h). Each case draws its magnitudes (and a
// frame period and phase) from the seed, so no two seeds see the same servo.
#pragma once

#include <functional>
#include <map>
#include <stdexcept>

#include "synth.h"
#include "synth_b.h"

namespace synth {

struct Case {
  std::string name;
  std::vector<std::string> expect;              // effect names (empty: no_missing_effect / unexplained)
  std::string verdict;                          // the expected verdict
  char generator = 'A';
  std::map<std::string, std::string> variant;   // the form expected where it is checked
  std::function<void(Truth&, std::mt19937_64&)> set;

  Truth truth(unsigned seed, const Conditions& c) const {
    Truth t;
    apply(c, &t);
    std::mt19937_64 rng(0xca5e0000u + seed);
    if (set) set(t, rng);
    return t;
  }
  Series record(const Truth& t, unsigned seed) const {
    return generator == 'B' ? generate_b(t, seed) : generate(t, seed);
  }
};

// magnitude factor U(0.7, 1.3)
inline double spread(std::mt19937_64& rng) { return std::uniform_real_distribution<double>(0.7, 1.3)(rng); }

// one effect of the catalogue on generator A's truth
struct EffectSetter {
  std::string name;
  std::function<void(Truth&, std::mt19937_64&)> set;
};

inline const std::vector<EffectSetter>& effect_setters() {
  static const std::vector<EffectSetter> e = {
      {"static_friction_threshold", [](Truth& t, std::mt19937_64& r) { t.i_th = 0.06 * spread(r); }},
      {"coulomb_friction", [](Truth& t, std::mt19937_64& r) { t.coulomb = 0.006 * spread(r); }},
      {"backlash", [](Truth& t, std::mt19937_64& r) { t.backlash_deg = 3 * spread(r); }},
      {"deadband", [](Truth& t, std::mt19937_64& r) { t.deadband_deg = 3 * spread(r); }},
      {"supply_sag", [](Truth& t, std::mt19937_64& r) { t.sag_ohm = 4 * spread(r); }},
      {"pwm_frame_delay",
       [](Truth& t, std::mt19937_64& r) {
         t.frame_s = std::uniform_real_distribution<double>(0.008, 0.025)(r);
         t.frame_phase_s = std::uniform_real_distribution<double>(0, t.frame_s)(r);
       }},
      {"current_limit", [](Truth& t, std::mt19937_64& r) { t.ilim = 0.22 * spread(r); }},
  };
  return e;
}

inline std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"null", {}, "no_missing_effect", 'A', {}, nullptr});
  const auto& es = effect_setters();
  for (const EffectSetter& e : es) {
    Case k{e.name, {e.name}, "explained", 'A', {}, e.set};
    if (e.name == "supply_sag") k.variant["supply_sag"] = "pwm_bridge";
    if (e.name == "deadband") k.variant["deadband"] = "dead_zone";
    if (e.name == "pwm_frame_delay") k.variant["pwm_frame_delay"] = "at_frame";
    c.push_back(k);
  }
  for (size_t a = 0; a < es.size(); ++a)
    for (size_t b = a + 1; b < es.size(); ++b) {
      const auto sa = es[a].set, sb = es[b].set;
      c.push_back({es[a].name + "+" + es[b].name, {es[a].name, es[b].name}, "explained", 'A', {},
                   [sa, sb](Truth& t, std::mt19937_64& r) {
                     sa(t, r);
                     sb(t, r);
                   }});
    }
  c.push_back({"cogging (outside the catalogue)", {}, "unexplained", 'A', {},
               [](Truth& t, std::mt19937_64& r) { t.cogging_nm = 0.01 * spread(r); }});
  // generator B
  c.push_back({"B: null", {}, "no_missing_effect", 'B', {}, nullptr});
  c.push_back({"B: backlash (rigid, restitution 0.2)", {"backlash"}, "explained", 'B', {{"backlash", "rigid"}},
               [](Truth& t, std::mt19937_64& r) { t.backlash_deg = 3 * spread(r); }});
  c.push_back({"B: supply_sag (PWM bridge, rail capacitor)", {"supply_sag"}, "explained", 'B',
               {{"supply_sag", "pwm_bridge_rail"}}, [](Truth& t, std::mt19937_64& r) { t.sag_ohm = 4 * spread(r); }});
  c.push_back({"B: supply_sag (linear driver, rail capacitor)", {"supply_sag"}, "explained", 'B',
               {{"supply_sag", "linear_driver_rail"}}, [](Truth& t, std::mt19937_64& r) {
                 t.sag_ohm = 4 * spread(r);
                 t.linear_driver = true;
               }});
  // the pulse train decoded at its falling edge (RC servos), k log-uniform
  // over 4-16 us/deg (1-2 ms over 180 deg is 5.6; 0.5-2.5 ms over 180 deg
  // 11.1)
  const auto falling = [](Truth& t, std::mt19937_64& r) {
    t.frame_s = std::uniform_real_distribution<double>(0.008, 0.025)(r);
    t.frame_phase_s = std::uniform_real_distribution<double>(0, t.frame_s)(r);
    t.pulse_s_per_deg = 4e-6 * std::pow(4.0, std::uniform_real_distribution<double>(0, 1)(r));
  };
  c.push_back({"B: pwm_frame_delay (falling edge)", {"pwm_frame_delay"}, "explained", 'B',
               {{"pwm_frame_delay", "falling_edge"}}, falling});
  c.push_back({"B: pwm_frame_delay (falling edge)+backlash", {"pwm_frame_delay", "backlash"}, "explained", 'B',
               {{"pwm_frame_delay", "falling_edge"}}, [falling](Truth& t, std::mt19937_64& r) {
                 falling(t, r);
                 t.backlash_deg = 3 * spread(r);
               }});
  c.push_back({"B: deadband (comparator)", {"deadband"}, "explained", 'B', {{"deadband", "comparator"}},
               [](Truth& t, std::mt19937_64& r) { t.deadband_deg = 3 * spread(r); }});
  c.push_back({"B: backlash+supply_sag", {"backlash", "supply_sag"}, "explained", 'B',
               {{"backlash", "rigid"}, {"supply_sag", "pwm_bridge_rail"}}, [](Truth& t, std::mt19937_64& r) {
                 t.backlash_deg = 3 * spread(r);
                 t.sag_ohm = 4 * spread(r);
               }});
  return c;
}

// the truth without one of its hidden effects (catalogue name)
inline Truth without_effect(Truth t, const std::string& name) {
  if (name == "static_friction_threshold") t.i_th = 0;
  else if (name == "coulomb_friction") t.coulomb = 0;
  else if (name == "backlash") t.backlash_deg = 0;
  else if (name == "deadband") t.deadband_deg = 0;
  else if (name == "supply_sag") t.sag_ohm = 0;
  else if (name == "pwm_frame_delay") t.frame_s = 0, t.frame_phase_s = 0, t.pulse_s_per_deg = 0;
  else if (name == "current_limit") t.ilim = 0;
  else throw std::invalid_argument("without_effect: no hidden effect named " + name);
  return t;
}

// the record of t as the meter would give it without noise and quantisation
inline Series exact_record(const Case& c, Truth t, unsigned seed) {
  t.exact = true;
  return c.record(t, seed);
}

// two exact records of t's servo (same seed: same sample times) apart, summed
// over the samples as (difference / the meter's sd)^2 per recorded channel
inline double records_apart(const Series& a, const Series& b, const Truth& t) {
  const Meter meter(t);
  double s = 0;
  for (size_t k = 0; k < a.t.size(); ++k) {
    const double da = (a.angle[k] - b.angle[k]) / meter.angle_sd();
    const double di = t.current_column ? (a.current[k] - b.current[k]) / meter.current_sd() : 0.0;
    s += da * da + di * di;
  }
  return s;
}

// An effect's size in a record: what it changes in the noiseless record (the
// same seed, so the same servo and sample times, without the effect), summed
// over the samples as (change / the meter's sd)^2 per recorded channel: the
// likelihood ratio of the effect at its true value, for a model that is
// otherwise right. A calibration cannot name an effect whose size is a few
// units: the record does not show it.
inline double effect_size(const Case& c, const Truth& t, unsigned seed, const std::string& name) {
  return records_apart(exact_record(c, t, seed), exact_record(c, without_effect(t, name), seed), t);
}

// the smallest size of the case's hidden effects in the record (-1: none
// hidden); the record with every effect made once
inline double weakest_effect_size(const Case& c, unsigned seed, const Conditions& cond) {
  if (c.expect.empty()) return -1;
  const Truth t = c.truth(seed, cond);
  const Series with = exact_record(c, t, seed);
  double m = -1;
  for (const std::string& e : c.expect) {
    const double s = records_apart(with, exact_record(c, without_effect(t, e), seed), t);
    m = m < 0 ? s : std::min(m, s);
  }
  return m;
}

// the case of that name (tests)
inline Case case_named(const std::string& name) {
  for (const Case& c : cases())
    if (c.name == name) return c;
  return {};
}

}  // namespace synth
