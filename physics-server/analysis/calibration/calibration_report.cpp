// The servo calibration's report (calibration_report.h).
#include "analysis/calibration/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "analysis/calibration/evidence_plots.h"
#include "analysis/calibration/regimes.h"
#include "analysis/calibration/svg_chart.h"
#include "analysis/calibration/text_format.h"

namespace chainsim {
namespace {

const char* const kMetric =
    "structured NRMSE on the held-out (odd) time blocks, models fitted on the even blocks: per channel "
    "(angle, and current when measured) the residual normalised by the measured channel's std, its mean "
    "square minus its white-noise part (half the mean square of first differences, the smaller of the two "
    "models' residuals), floored at 0; sqrt of the mean over channels";

void write_file(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw ReportError(path + ": cannot write");
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) throw ReportError(path + ": cannot write");
}

// contiguous runs of one regime, with the error before and after there
nlohmann::ordered_json regions_json(const ServoCalibration& c) {
  const MeasuredRecord& m = c.problem.m;
  const Residual& rb = c.before.residual;
  const Residual& ra = c.after.residual;
  nlohmann::ordered_json regions = nlohmann::json::array();
  for (const RegimeRun& run : regime_runs(c.regime)) {
    double e0 = 0, e1 = 0;
    for (size_t k = run.first; k <= run.last; ++k) e0 += rb.energy(k), e1 += ra.energy(k);
    const double cnt = (run.last - run.first + 1) * (m.has_current ? 2.0 : 1.0);
    nlohmann::ordered_json r;
    r["t0_s"] = m.t[run.first];
    r["t1_s"] = m.t[run.last];
    r["label"] = regime_names()[run.regime];
    r["error"] = std::sqrt(e0 / cnt);
    r["error_after"] = std::sqrt(e1 / cnt);
    regions.push_back(r);
  }
  return regions;
}

// per regime: its share of time and the error before and after on all data
nlohmann::ordered_json regimes_json(const ServoCalibration& c) {
  const size_t n = c.problem.m.size();
  const BlockSplit& split = c.problem.split;
  nlohmann::ordered_json jr;
  for (size_t g = 0; g < regime_names().size(); ++g) {
    std::vector<bool> mask(n, false);
    size_t cnt = 0;
    for (size_t k = 0; k < n; ++k)
      if (c.regime[k] == static_cast<int>(g)) mask[k] = true, ++cnt;
    if (!cnt) continue;
    jr[regime_names()[g]] = {{"share", double(cnt) / n},
                             {"error_before", nrmse(c.before.residual, split, Samples::all, &mask)},
                             {"error_after", nrmse(c.after.residual, split, Samples::all, &mask)}};
  }
  return jr;
}

// an effect's parameters (and their intervals) from x at its offset
nlohmann::ordered_json params_json(const Effect& ef, const std::vector<double>& x, size_t o) {
  nlohmann::ordered_json j;
  for (size_t q = 0; q < ef.params.size(); ++q) j[ef.params[q].name] = x[o + q];
  return j;
}

nlohmann::ordered_json candidates_json(const ServoCalibration& c) {
  nlohmann::ordered_json jc = nlohmann::json::array();
  for (size_t ri = 0; ri < c.search.rounds.size(); ++ri) {
    const SearchRound& rd = c.search.rounds[ri];
    for (const Candidate& cd : rd.candidates) {
      const Effect& ef = effect_catalogue()[cd.effect];
      nlohmann::ordered_json j;
      j["round"] = ri + 1;
      j["name"] = ef.name;
      if (*ef.variant) j["variant"] = ef.variant;
      j["params"] = params_json(ef, cd.fit.x, param_count(rd.reference.effects));
      j["held_out"] = cd.fit.held;
      j["profile_lr"] = cd.profile.stat;
      j["profile_lr_crit"] = cd.profile.crit;
      j["held_out_gain"] = cd.held_out.gain;
      j["held_out_lr"] = cd.held_out.stat;
      j["held_out_lr_crit"] = cd.held_out.crit;
      j["signature"] = cd.signature;
      j["accepted"] = cd.accepted;
      j["why"] = cd.why;
      jc.push_back(j);
    }
  }
  return jc;
}

// the accepted candidate of an effect (by position in the final model)
const Candidate* accepted_candidate(const ServoCalibration& c, size_t index) {
  size_t n = 0;
  for (const SearchRound& rd : c.search.rounds)
    for (const Candidate& cd : rd.candidates)
      if (cd.accepted && n++ == index) return &cd;
  return nullptr;
}

std::string evidence_file(const ServoCalibration& c, size_t index) {
  return "evidence_" + std::to_string(index + 1) + "_" + effect_catalogue()[c.final_fit.effects[index]].name + ".svg";
}

}  // namespace

nlohmann::ordered_json calibration_report_json(const ServoCalibration& c) {
  const Fit& fin = c.final_fit;
  const Fit& cur = c.search.model;
  nlohmann::ordered_json j;
  j["verdict"] = c.verdict;
  j["effects"] = nlohmann::json::array();
  const std::vector<EffectEvidence> evidence = effect_evidence(c);
  for (size_t e = 0; e < fin.effects.size(); ++e) {
    const Effect& ef = effect_catalogue()[fin.effects[e]];
    const size_t o = param_offset(fin.effects, e);
    nlohmann::ordered_json je;
    je["name"] = ef.name;
    if (*ef.variant) je["variant"] = ef.variant;
    je["form"] = ef.form;
    je["params"] = params_json(ef, fin.x, o);
    for (size_t q = 0; q < ef.params.size(); ++q)
      je["ci95"][ef.params[q].name] = {c.ci[o + q].first, c.ci[o + q].second};
    if (const Candidate* cd = accepted_candidate(c, e)) {
      je["tests"] = {{"profile_lr", cd->profile.stat},         {"profile_lr_crit", cd->profile.crit},
                     {"correlation_inflation", cd->profile.inflation}, {"held_out_gain", cd->held_out.gain},
                     {"held_out_lr", cd->held_out.stat},       {"held_out_lr_crit", cd->held_out.crit}};
    }
    for (const VariantChoice& v : c.search.variants)
      if (v.effect == ef.name)
        je["variant_choice"] = {{"chosen", v.chosen}, {"other", v.other}, {"held_out_lr", v.t},
                                {"distinguished", v.distinguished}, {"why", v.why}};
    if (e < evidence.size()) {
      nlohmann::ordered_json jw = nlohmann::json::array();
      for (const EvidenceWindow& w : evidence[e].windows)
        jw.push_back({{"t0_s", c.problem.m.t[w.first]}, {"t1_s", c.problem.m.t[w.last]}, {"regime", w.regime},
                      {"error_before", w.error_before}, {"error_after", w.error_after}});
      je["evidence"] = {{"where", evidence[e].where}, {"plot", evidence_file(c, e)}, {"windows", jw}};
    }
    j["effects"].push_back(je);
  }
  j["gap_before"] = c.gap_before;
  j["gap_after"] = c.gap_after;
  j["metric"] = kMetric;
  j["nrmse_before"] = c.base.held;
  j["nrmse_after"] = cur.held;
  j["nrmse_datasheet"] = c.nrmse_datasheet;
  j["whiteness_before"] = c.base.white;
  j["whiteness_after"] = cur.white;
  j["whiteness_threshold"] = kWhiteMax;
  nlohmann::ordered_json jb;
  const std::vector<double> bv = base_values(model_config(c.problem.datasheet, fin.effects, fin.x));
  for (int i = 0; i < kNumBase; ++i) {
    jb[kBaseNames[i]]["value"] = bv[i];
    jb[kBaseNames[i]]["factor"] = fin.x[i];
    jb[kBaseNames[i]]["ci95_factor"] = {c.ci[i].first, c.ci[i].second};
  }
  j["base"] = jb;
  j["regions"] = regions_json(c);
  j["regimes"] = regimes_json(c);
  j["candidates"] = candidates_json(c);
  j["ode_check_max_angle_diff_deg"] = c.ode_check_max_angle_diff_deg;
  j["model_runs"] = c.model_runs;
  return j;
}

std::string calibration_report_md(const ServoCalibration& c, const nlohmann::ordered_json& j,
                                  const std::string& bench_file, const std::string& measured_file) {
  const MeasuredRecord& m = c.problem.m;
  const Fit& fin = c.final_fit;
  const Fit& cur = c.search.model;
  const auto& ci = c.ci;
  std::ostringstream md;
  md << "# Servo calibration report\n\nBench file: `" << (bench_file.empty() ? "(defaults)" : bench_file)
     << "`, measurement: `" << measured_file << "` (" << m.size() << " samples, " << fmt_g(m.t.back() - m.t.front())
     << " s).\n\n";
  md << "**Verdict: " << c.verdict << "**. Gap (" << j["metric"].get<std::string>() << "): refitted base "
     << fmt_g(c.gap_before) << ", with effects " << fmt_g(c.gap_after) << ". Plain held-out NRMSE: datasheet "
     << fmt_g(c.nrmse_datasheet) << ", refitted base " << fmt_g(c.base.held) << ", with effects "
     << fmt_g(cur.held) << ". Whiteness of the held-out residual (rms / rms of differences x sqrt 2; "
     << "noise ~1, threshold " << kWhiteMax << "): " << fmt_g(c.base.white, 3) << " -> " << fmt_g(cur.white, 3)
     << ".\n\n![angle](angle.svg)\n\n";
  if (m.has_current) md << "![current](current.svg)\n\n";
  md << "![residual](residual.svg)\n\n## Fitted parameters (all data, 95 % intervals)\n\n| parameter | value | 95 % "
        "CI |\n|---|---|---|\n";
  for (int i = 0; i < kNumBase; ++i)
    md << "| " << kBaseNames[i] << " (x datasheet) | " << fmt_g(fin.x[i]) << " | [" << fmt_g(ci[i].first) << ", "
       << fmt_g(ci[i].second) << "] |\n";
  for (size_t e = 0; e < fin.effects.size(); ++e) {
    const Effect& ef = effect_catalogue()[fin.effects[e]];
    const size_t o = param_offset(fin.effects, e);
    for (size_t q = 0; q < ef.params.size(); ++q)
      md << "| " << ef.name << (*ef.variant ? std::string(" (") + ef.variant + ")" : "") << "." << ef.params[q].name
         << " | " << fmt_g(fin.x[o + q]) << " | [" << fmt_g(ci[o + q].first) << ", " << fmt_g(ci[o + q].second)
         << "] |\n";
  }
  if (!fin.effects.empty()) {
    md << "\n## Effects found\n\n";
    for (const auto& je : j["effects"]) {
      md << "* **" << je["name"].get<std::string>() << "**";
      if (je.contains("variant")) md << ", form `" << je["variant"].get<std::string>() << "`";
      md << " (" << je["form"].get<std::string>() << ")";
      if (je.contains("tests"))
        md << ": likelihood ratio " << fmt_g(je["tests"]["profile_lr"].get<double>()) << " >= "
           << fmt_g(je["tests"]["profile_lr_crit"].get<double>()) << " (its 95 % profile interval excludes the null), "
           << "held-out likelihood ratio " << fmt_g(je["tests"]["held_out_lr"].get<double>(), 4) << " >= "
           << fmt_g(je["tests"]["held_out_lr_crit"].get<double>(), 3);
      if (je.contains("variant_choice"))
        md << "; form: " << je["variant_choice"]["why"].get<std::string>();
      md << ".\n";
    }
    md << "\n## Where the effects act (measured vs the model without the effect and the final model)\n\n";
    for (const auto& je : j["effects"])
      if (je.contains("evidence"))
        md << "**" << je["name"].get<std::string>() << "** at " << je["evidence"]["where"].get<std::string>()
           << ":\n\n![" << je["name"].get<std::string>() << "](" << je["evidence"]["plot"].get<std::string>()
           << ")\n\n";
  }
  md << "\n## Residual by regime (all data)\n\n| regime | share of time | error before | error after "
        "|\n|---|---|---|---|\n";
  const auto& jr = j["regimes"];
  for (auto it = jr.begin(); it != jr.end(); ++it)
    md << "| " << it.key() << " | " << fmt_g((*it)["share"].get<double>(), 3) << " | "
       << fmt_g((*it)["error_before"].get<double>(), 3) << " | " << fmt_g((*it)["error_after"].get<double>(), 3)
       << " |\n";
  md << "\n## Worst regions before\n\n| t0 (s) | t1 (s) | regime | error before | error after "
        "|\n|---|---|---|---|---|\n";
  std::vector<nlohmann::ordered_json> rs(j["regions"].begin(), j["regions"].end());
  std::sort(rs.begin(), rs.end(), [](const auto& x, const auto& y) { return x["error"] > y["error"]; });
  for (size_t i = 0; i < std::min<size_t>(10, rs.size()); ++i)
    md << "| " << fmt_g(rs[i]["t0_s"].get<double>()) << " | " << fmt_g(rs[i]["t1_s"].get<double>()) << " | "
       << rs[i]["label"].get<std::string>() << " | " << fmt_g(rs[i]["error"].get<double>(), 3) << " | "
       << fmt_g(rs[i]["error_after"].get<double>(), 3) << " |\n";
  md << "\n## Candidates\n\nEach round re-fits the current model from two starts (the reference), fits each "
        "effect on top (a form that refines another, a supply on a rail capacitor, only where the simpler form's "
        "profile interval excludes the null and it passes the held-out test uncorrected; one whose first start has not "
        "gained the chi-square median of the profile statistic after 2 (2n + 1) model runs is not fitted in full), "
        "and accepts the best "
        "held-out gain that passes both tests: the likelihood ratio against the reference (its 95 % profile "
        "interval excludes the effect's null) and the same ratio on the held-out blocks, against the chi-square "
        "point at 5 % / the number of candidates. Signature = share of the reference's residual in the regimes "
        "where the effect acts, over their share of time.\n\n| round | effect | values | held-out "
        "NRMSE | signature | decision |\n|---|---|---|---|---|---|\n";
  const auto& jc = j["candidates"];
  for (const auto& cd : jc) {
    std::string vals;
    for (auto it = cd["params"].begin(); it != cd["params"].end(); ++it)
      vals += (vals.empty() ? "" : ", ") + fmt_g(it->get<double>()) + " " + it.key();
    md << "| " << cd["round"].get<int>() << " | " << cd["name"].get<std::string>()
       << (cd.contains("variant") ? " (" + cd["variant"].get<std::string>() + ")" : "") << " | " << vals << " | "
       << fmt_g(cd["held_out"].get<double>()) << " | " << fmt_g(cd["signature"].get<double>(), 3) << " | "
       << cd["why"].get<std::string>() << " |\n";
  }
  if (jc.empty()) md << "| - | none tried: the refitted base already leaves a noise-like residual | | | | |\n";
  md << "\nCheck: the final model on the bench's ODE stand differs from the fast solver by at most "
     << fmt_g(c.ode_check_max_angle_diff_deg, 3) << " degrees.\n";
  return md.str();
}

void write_calibration_report(const ServoCalibration& c, const std::string& bench_file,
                              const std::string& measured_file, const std::string& out_dir) {
  const nlohmann::ordered_json j = calibration_report_json(c);
  write_file(out_dir + "/report.json", j.dump(2) + "\n");
  const MeasuredRecord& m = c.problem.m;
  const size_t n = m.size();
  std::vector<double> sb(n), sa(n), ib(n), ia(n), ra(n), rb(n);
  for (size_t k = 0; k < n; ++k) {
    sb[k] = c.before.sim[k].angle_deg, sa[k] = c.after.sim[k].angle_deg;
    ib[k] = c.before.sim[k].current_a, ia[k] = c.after.sim[k].current_a;
    rb[k] = sb[k] - m.angle[k], ra[k] = sa[k] - m.angle[k];
  }
  write_file(out_dir + "/angle.svg",
             svg_chart("angle: measured vs model before / after", "deg", m.t,
                       {{"measured", "#000", m.angle}, {"set-point", "#aaa", m.sp}, {"before", "#d62728", sb},
                        {"after", "#1f77b4", sa}}));
  write_file(out_dir + "/residual.svg", svg_chart("angle residual (model - measured)", "deg", m.t,
                                                  {{"before", "#d62728", rb}, {"after", "#1f77b4", ra}}));
  if (m.has_current)
    write_file(out_dir + "/current.svg",
               svg_chart("filtered current: measured vs model", "A", m.t,
                         {{"measured", "#000", m.current}, {"before", "#d62728", ib}, {"after", "#1f77b4", ia}}));
  const std::vector<EffectEvidence> evidence = effect_evidence(c);
  for (size_t e = 0; e < evidence.size(); ++e)
    write_file(out_dir + "/" + evidence_file(c, e), evidence_svg(c, evidence[e]));
  write_file(out_dir + "/report.md", calibration_report_md(c, j, bench_file, measured_file));
}

}  // namespace chainsim
