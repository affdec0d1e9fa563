// Evidence plots of the accepted effects (evidence_plots.h).
#include "analysis/calibration/evidence_plots.h"

#include <algorithm>
#include <cmath>

#include "analysis/calibration/regimes.h"
#include "analysis/calibration/svg_chart.h"
#include "analysis/calibration/text_format.h"

namespace chainsim {
namespace {

constexpr double kMargin_s = 0.02, kMaxWindow_s = 0.25;

std::string where_of(const Effect& e) {
  const std::string& r = e.regimes.front();
  if (r == "hold") return "holds";
  if (r == "reversal") return "reversals";
  if (r == "step_onset") return "frame edges (set-point changes)";
  if (r == "high_current") return "high-current moves";
  return r;
}

double window_error(const Residual& r, size_t a, size_t b) {
  double e = 0;
  for (size_t k = a; k <= b; ++k) e += r.energy(k);
  return std::sqrt(e / ((b - a + 1) * r.channels()));
}

}  // namespace

std::vector<EffectEvidence> effect_evidence(const ServoCalibration& c) {
  const MeasuredRecord& m = c.problem.m;
  const std::vector<int>& effects = c.search.model.effects;
  std::vector<EffectEvidence> out;
  for (size_t i = 0; i < effects.size() && i < c.without.size(); ++i) {
    const Effect& ef = effect_catalogue()[effects[i]];
    EffectEvidence ev;
    ev.index = i;
    ev.where = where_of(ef);
    for (const RegimeRun& run : regime_runs(c.regime)) {
      const std::string& name = regime_names()[run.regime];
      if (std::find(ef.regimes.begin(), ef.regimes.end(), name) == ef.regimes.end()) continue;
      // the run with a margin, at most kMaxWindow_s long
      size_t a = run.first, b = run.last;
      while (a > 0 && m.t[run.first] - m.t[a - 1] <= kMargin_s) --a;
      while (b + 1 < m.size() && m.t[b + 1] - m.t[run.last] <= kMargin_s) ++b;
      while (b > a && m.t[b] - m.t[a] > kMaxWindow_s) --b;
      if (b <= a + 2) continue;
      ev.windows.push_back({a, b, name, window_error(c.without[i].residual, a, b), window_error(c.after.residual, a, b)});
    }
    std::sort(ev.windows.begin(), ev.windows.end(), [](const EvidenceWindow& x, const EvidenceWindow& y) {
      return x.error_before - x.error_after > y.error_before - y.error_after;
    });
    if (ev.windows.size() > 3) ev.windows.resize(3);
    out.push_back(std::move(ev));
  }
  return out;
}

std::string evidence_svg(const ServoCalibration& c, const EffectEvidence& e) {
  const MeasuredRecord& m = c.problem.m;
  const Fit& fin = c.search.model;
  const int eff = fin.effects[e.index];
  const Effect& ef = effect_catalogue()[eff];
  // the frame clock's edges, for a frame effect
  double period = 0, phase = 0;
  if (ef.fit == EffectFit::frame_clock) {
    const size_t o = param_offset(fin.effects, e.index);
    period = fin.x[o] * ef.params[0].to_model, phase = fin.x[o + 1] * ef.params[1].to_model;
  }
  const ModelRun& before = c.without[e.index];
  std::vector<SvgPanel> angle, current;
  for (const EvidenceWindow& w : e.windows) {
    SvgPanel pa, pi;
    for (size_t k = w.first; k <= w.last; ++k) pa.t.push_back(m.t[k]);
    pi.t = pa.t;
    auto slice = [&](auto get) {
      std::vector<double> v;
      for (size_t k = w.first; k <= w.last; ++k) v.push_back(get(k));
      return v;
    };
    const std::string err = fmt_g(w.error_before, 3) + " -> " + fmt_g(w.error_after, 3);
    pa.title = w.regime + " at " + fmt_g(m.t[w.first], 4) + " s (error " + err + ")";
    pa.ylabel = "angle (deg)";
    pa.series = {{"measured", "#000", slice([&](size_t k) { return m.angle[k]; })},
                 {"set-point", "#aaa", slice([&](size_t k) { return m.sp[k]; })},
                 {"without it", "#d62728", slice([&](size_t k) { return before.sim[k].angle_deg; })},
                 {"final model", "#1f77b4", slice([&](size_t k) { return c.after.sim[k].angle_deg; })}};
    if (period > 0)
      for (double tf = m.t.front() + phase; tf <= m.t[w.last]; tf += period)
        if (tf >= m.t[w.first]) pa.marks.push_back(tf);
    angle.push_back(pa);
    if (m.has_current) {
      pi.title = "current";
      pi.ylabel = "current (A)";
      pi.series = {{"measured", "#000", slice([&](size_t k) { return m.current[k]; })},
                   {"set-point", "#aaa", std::vector<double>()},
                   {"without it", "#d62728", slice([&](size_t k) { return before.sim[k].current_a; })},
                   {"final model", "#1f77b4", slice([&](size_t k) { return c.after.sim[k].current_a; })}};
      pi.series.erase(pi.series.begin() + 1);
      pi.marks = pa.marks;
      current.push_back(pi);
    }
  }
  std::vector<SvgPanel> all = angle;
  all.insert(all.end(), current.begin(), current.end());
  const std::string title = std::string(ef.name) + (*ef.variant ? std::string(" (") + ef.variant + ")" : "") +
                            ": where it acts (" + e.where + "), measured vs the model without it and the final model";
  return svg_panel_grid(title, all, std::max<int>(1, static_cast<int>(e.windows.size())));
}

}  // namespace chainsim
