// The robot calibration's report (robot_report.h).
#include "analysis/robot_calibration/robot_report.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace chainsim {
namespace {

nlohmann::ordered_json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  if (!f) throw RobotError(path + ": cannot write");
}

}  // namespace

nlohmann::ordered_json robot_report_json(const RobotReportInputs& in, const RobotSearch& s) {
  const std::vector<SpeedRow>& rows = in.speeds.rows;
  const std::string& key = in.speeds.key_name;
  const size_t n = rows.size();
  auto knob = [](int k) -> const Knob& { return robot_knobs()[k]; };
  nlohmann::ordered_json jc = nlohmann::ordered_json::array();
  for (const KnobCandidate& c : s.candidates) {
    nlohmann::ordered_json jp = nlohmann::ordered_json::object();
    for (const auto& [k, f] : c.fit.st)
      jp[knob(k).name] = {{"factor", f}, {"value", f * in.nominal[k]}, {"nominal", in.nominal[k]}};
    jc.push_back({{"round", c.round}, {"name", knob(c.knob).name}, {"param", knob(c.knob).param},
                  {"gap", c.fit.gap}, {"settings", jp}, {"evaluations", c.fit.evals}, {"accepted", c.accepted},
                  {"why", c.why}});
  }
  // what stays: the rows the fitted model misses by more than the table's resolution
  nlohmann::ordered_json jmiss = nlohmann::ordered_json::array();
  for (size_t i = 0; i < n; ++i)
    if (std::fabs(s.after[i] - rows[i].real) > kTableResolution)
      jmiss.push_back({{key, rows[i].key}, {"real", rows[i].real}, {"after", s.after[i]},
                       {"error", s.after[i] - rows[i].real}});
  nlohmann::ordered_json j;
  j["kind"] = "robot";
  j["table"] = in.table;
  j["scene_template"] = in.scene_template;
  j["key"] = key;
  j["duration_s"] = in.duration_s;
  j["window_start_s"] = in.window_start_s;
  j["metric"] = "RMS over the rows of simulated - real speed, cm/s";
  j["verdict"] = s.verdict;
  j["gap_before"] = s.gap_before;
  j["gap_after"] = s.gap_after;
  j["gap_paper_sim"] = number_or_null(s.paper_gap);
  j["gap_leave_one_out"] = number_or_null(s.leave_one_out_gap);
  j["table_resolution_cm_s"] = kTableResolution;
  nlohmann::ordered_json je = nlohmann::ordered_json::array();
  for (int k : s.accepted)
    je.push_back({{"name", knob(k).name}, {"param", knob(k).param}, {"meaning", knob(k).meaning},
                  {"nominal", in.nominal[k]}, {"factor", s.model.at(k)}, {"value", s.model.at(k) * in.nominal[k]}});
  j["effects"] = je;
  nlohmann::ordered_json tried = nlohmann::ordered_json::array();
  for (int k : in.usable) tried.push_back(knob(k).name);
  j["catalogue_applicable"] = tried;
  nlohmann::ordered_json jr = nlohmann::ordered_json::array();
  for (size_t i = 0; i < n; ++i)
    jr.push_back({{key, rows[i].key}, {"real", rows[i].real}, {"paper_sim", number_or_null(rows[i].paper)},
                  {"before", s.before[i]}, {"after", s.after[i]}, {"leave_one_out", number_or_null(s.leave_one_out[i])}});
  j["rows"] = jr;
  j["missed"] = jmiss;
  j["candidates"] = jc;
  nlohmann::ordered_json jpairs = nlohmann::ordered_json::array();
  for (const PairCandidate& p : s.pairs) {
    nlohmann::ordered_json jp = nlohmann::ordered_json::object();
    for (const auto& [k, f] : p.fit.st)
      jp[knob(k).name] = {{"factor", f}, {"value", f * in.nominal[k]}, {"nominal", in.nominal[k]}};
    jpairs.push_back({{"names", {knob(p.a).name, knob(p.b).name}},
                      {"gap", p.fit.gap},
                      {"gap_alone", {p.single_a, p.single_b}},
                      {"gap_leave_one_out", number_or_null(p.leave_one_out_gap)},
                      {"settings", jp},
                      {"evaluations", p.fit.evals},
                      {"accepted", p.accepted},
                      {"why", p.why}});
  }
  j["pairs"] = jpairs;
  nlohmann::ordered_json jal = nlohmann::ordered_json::array();
  for (const Alias& a : s.aliases) {
    nlohmann::ordered_json names = nlohmann::ordered_json::array(), jp = nlohmann::ordered_json::object(),
                           chosen = nlohmann::ordered_json::array();
    for (const auto& [k, f] : a.other) names.push_back(knob(k).name), jp[knob(k).name] = f;
    for (const auto& [k, f] : a.chosen) chosen.push_back(knob(k).name);
    jal.push_back({{"names", names}, {"factors", jp}, {"gap", a.gap_other}, {"speed_difference_rms", a.difference},
                   {"alias_of", chosen}});
  }
  j["aliases"] = jal;
  j["runs"] = in.runs;
  j["evaluations"] = in.settings;
  j["run_wall_s"] = in.run_wall_s;
  j["wall_s"] = in.wall_s;
  return j;
}

std::string robot_report_md(const RobotReportInputs& in, const RobotSearch& s, const nlohmann::ordered_json& j) {
  const std::vector<SpeedRow>& rows = in.speeds.rows;
  const std::string& key = in.speeds.key_name;
  const size_t n = rows.size();
  std::ostringstream md;
  md << "# Robot-level calibration report\n\nTable `" << in.table << "`, scenes `" << in.scene_template << "` ("
     << n << " rows; runs of " << fmt_fixed(in.duration_s, 1) << " s, speed of the head along the pipe axis from "
     << fmt_fixed(in.window_start_s, 1) << " s).\n\n**Verdict: " << s.verdict
     << "**. Gap (RMS of simulated - real, cm/s): "
     << "before " << fmt_fixed(s.gap_before) << ", after " << fmt_fixed(s.gap_after);
  if (std::isfinite(s.leave_one_out_gap)) md << " (leave-one-row-out " << fmt_fixed(s.leave_one_out_gap) << ")";
  if (std::isfinite(s.paper_gap)) md << "; the paper's simulator " << fmt_fixed(s.paper_gap);
  md << ". Table resolution: +-" << kTableResolution << " cm/s.\n\n";
  md << "| " << key << " | real | paper's sim | before | after | leave-one-out |\n|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < n; ++i)
    md << "| " << rows[i].key << " | " << fmt_fixed(rows[i].real, 2) << " | "
       << (std::isfinite(rows[i].paper) ? fmt_fixed(rows[i].paper, 2) : "-") << " | " << fmt_fixed(s.before[i], 2)
       << " | " << fmt_fixed(s.after[i], 2) << " | "
       << (std::isfinite(s.leave_one_out[i]) ? fmt_fixed(s.leave_one_out[i], 2) : "-") << " |\n";
  md << "\n## Effects\n\n";
  if (s.accepted.empty()) md << "None accepted.\n";
  for (int k : s.accepted) {
    const Knob& kb = robot_knobs()[k];
    md << "* `" << kb.name << "` (" << kb.meaning << "): " << kb.param << " " << fmt_fixed(in.nominal[k], 4)
       << " -> " << fmt_fixed(s.model.at(k) * in.nominal[k], 4) << " (x" << fmt_fixed(s.model.at(k)) << ")\n";
  }
  if (!s.aliases.empty()) {
    md << "\n**Alias**: the table cannot tell the effects above from";
    for (const auto& a : j["aliases"]) {
      std::string sep;
      md << " ";
      for (const auto& nm : a["names"]) md << sep << "`" << nm.get<std::string>() << "`", sep = " + ";
      md << " (";
      sep.clear();
      for (auto it = a["factors"].begin(); it != a["factors"].end(); ++it)
        md << sep << it.key() << " x" << fmt_fixed(it->get<double>()), sep = ", ";
      md << "; gap " << fmt_fixed(a["gap"].get<double>()) << ", speeds within "
         << fmt_fixed(a["speed_difference_rms"].get<double>()) << " cm/s RMS)";
    }
    md << ": both reproduce it within its resolution. A table with more rows (other slopes or loads) would "
          "tell them apart.\n";
  }
  if (!j["missed"].empty()) {
    md << "\nStill missed by more than the table's resolution:";
    for (const auto& m : j["missed"])
      md << " " << m[key].get<std::string>() << " (" << fmt_fixed(m["error"].get<double>(), 2) << " cm/s)";
    md << ". No effect of the catalogue explains it.\n";
  }
  md << "\n## Candidates\n\n| round | effect | gap after fit | setting | evaluations | decision "
        "|\n|---|---|---|---|---|---|\n";
  for (const auto& c : j["candidates"]) {
    std::string set;
    for (auto it = c["settings"].begin(); it != c["settings"].end(); ++it)
      set += it.key() + " = " + fmt_fixed((*it)["value"].get<double>(), 4) + " ";
    md << "| " << c["round"].get<int>() << " | " << c["name"].get<std::string>() << " | "
       << fmt_fixed(c["gap"].get<double>()) << " | " << set << "| " << c["evaluations"].get<int>() << " | "
       << c["why"].get<std::string>() << " |\n";
  }
  if (!j["pairs"].empty()) {
    md << "\n## Pairs fitted jointly\n\n| pair | gap alone | gap together | leave-one-out | factors | evaluations "
          "| decision |\n|---|---|---|---|---|---|---|\n";
    for (const auto& p : j["pairs"]) {
      std::string set;
      for (auto it = p["settings"].begin(); it != p["settings"].end(); ++it)
        set += it.key() + " x" + fmt_fixed((*it)["factor"].get<double>()) + " ";
      md << "| " << p["names"][0].get<std::string>() << " + " << p["names"][1].get<std::string>() << " | "
         << fmt_fixed(p["gap_alone"][0].get<double>()) << ", " << fmt_fixed(p["gap_alone"][1].get<double>())
         << " | " << fmt_fixed(p["gap"].get<double>()) << " | "
         << (p["gap_leave_one_out"].is_null() ? "-" : fmt_fixed(p["gap_leave_one_out"].get<double>())) << " | "
         << set << "| " << p["evaluations"].get<int>() << " | " << p["why"].get<std::string>() << " |\n";
    }
  }
  md << "\n" << in.runs << " runs (" << in.settings << " settings), " << fmt_fixed(in.wall_s, 1) << " s wall.\n";
  return md.str();
}

void write_robot_report(const RobotReportInputs& in, const RobotSearch& s, const std::string& out_dir) {
  const nlohmann::ordered_json j = robot_report_json(in, s);
  write_text(out_dir + "/report.json", j.dump(2) + "\n");
  write_text(out_dir + "/report.md", robot_report_md(in, s, j));
}

}  // namespace chainsim
