#include "optimize/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "optimize/verify.h"
#include "text/number_text.h"

namespace chainsim {

namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// a number in the report: empty for NaN, "never" for +inf
// a report cell's word for what is not a finite number: blank for NaN, "never"
// for +inf (a time never reached)
std::string not_finite_word(double v) { return std::isnan(v) ? "" : v > 0 ? "never" : "-inf"; }

// printf's %.<digits>g, or the word above
std::string shown_num(double v, int digits = 6) {
  return std::isfinite(v) ? general_text(v, digits) : not_finite_word(v);
}

// printf's %.<decimals>f, or the word above
std::string shown_fixed(double v, int decimals) {
  return std::isfinite(v) ? fixed_text(v, decimals) : not_finite_word(v);
}

// the fitness plot: one polyline per series over the generations
std::string plot_svg(const Problem& pr, const std::vector<GenerationStats>& st) {
  if (st.empty()) return "<p>No generation finished yet.</p>";
  const double W = 780, H = 340, L = 90, R = 150, T = 20, B = 45;
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& s : st)
    for (double v : {s.best, s.mean, s.worst}) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!(hi > lo)) {
    hi = lo + 1;
    lo -= 1;
  }
  const int g0 = st.front().generation, g1 = std::max(st.back().generation, g0 + 1);
  auto X = [&](double g) { return L + (W - L - R) * (g - g0) / (g1 - g0); };
  auto Y = [&](double v) { return T + (H - T - B) * (1 - (v - lo) / (hi - lo)); };
  std::ostringstream o;
  o << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif' font-size='12'>";
  o << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B
    << "' fill='none' stroke='#888'/>";
  for (int k = 0; k <= 4; ++k) {
    const double v = lo + (hi - lo) * k / 4;
    o << "<text x='" << L - 6 << "' y='" << Y(v) + 4 << "' text-anchor='end'>" << shown_num(v, 4) << "</text>";
    o << "<line x1='" << L << "' x2='" << W - R << "' y1='" << Y(v) << "' y2='" << Y(v) << "' stroke='#eee'/>";
  }
  const int step = std::max(1, (g1 - g0) / 10);
  for (int g = g0; g <= g1; g += step)
    o << "<text x='" << X(g) << "' y='" << H - B + 16 << "' text-anchor='middle'>" << g << "</text>";
  o << "<text x='" << (L + W - R) / 2 << "' y='" << H - 8 << "' text-anchor='middle'>generation</text>";
  o << "<text x='14' y='" << (T + H - B) / 2 << "' transform='rotate(-90 14," << (T + H - B) / 2
    << ")' text-anchor='middle'>fitness (" << (pr.objective.maximize ? "higher" : "lower") << " is better)</text>";
  struct Series {
    const char* name;
    const char* colour;
    double GenerationStats::*field;
  };
  const Series series[] = {{"best", "#1a7f37", &GenerationStats::best},
                           {"mean", "#0969da", &GenerationStats::mean},
                           {"worst", "#cf222e", &GenerationStats::worst},
                           {"best so far", "#222", &GenerationStats::best_so_far}};
  int row = 0;
  for (const auto& s : series) {
    o << "<polyline fill='none' stroke='" << s.colour << "' stroke-width='" << (row == 3 ? 1 : 2)
      << "'" << (row == 3 ? " stroke-dasharray='4 3'" : "") << " points='";
    for (const auto& g : st) o << X(g.generation) << "," << Y(g.*(s.field)) << " ";
    o << "'/>";
    o << "<line x1='" << W - R + 12 << "' x2='" << W - R + 36 << "' y1='" << T + 12 + 18 * row << "' y2='"
      << T + 12 + 18 * row << "' stroke='" << s.colour << "' stroke-width='2'/><text x='" << W - R + 42
      << "' y='" << T + 16 + 18 * row << "'>" << s.name << "</text>";
    ++row;
  }
  o << "</svg>";
  return o.str();
}

}  // namespace

std::vector<GenerationStats> generation_stats(const Problem& pr, const std::vector<HistoryRow>& rows) {
  std::map<int, GenerationStats> by_gen;
  std::map<int, double> sums;
  for (const auto& r : rows) {
    GenerationStats& s = by_gen[r.generation];
    const double f = r.result.fitness;
    if (s.individuals == 0) s.best = s.worst = f;
    s.generation = r.generation;
    if (better_fitness(pr.objective, f, s.best)) s.best = f;
    if (better_fitness(pr.objective, s.worst, f)) s.worst = f;
    sums[r.generation] += f;
    ++s.individuals;
    s.failed += r.result.failed;
    s.cached += r.cached;
    s.wall_s += r.result.wall_s;
  }
  std::vector<GenerationStats> out;
  for (auto& [g, s] : by_gen) {
    s.mean = sums[g] / s.individuals;
    s.best_so_far = out.empty() || better_fitness(pr.objective, s.best, out.back().best_so_far) ? s.best
                                                                                                 : out.back().best_so_far;
    out.push_back(s);
  }
  return out;
}

std::string report_html(const Problem& pr, const std::vector<HistoryRow>& rows, const BestSoFar& best,
                        const ReportNotes& notes, const std::string& replay_html) {
  const std::vector<GenerationStats> st = generation_stats(pr, rows);
  std::ostringstream o;
  o << "<!doctype html><html><head><meta charset='utf-8'><title>chainsim optimize: " << esc(pr.name)
    << "</title><style>body{font-family:sans-serif;margin:2em;max-width:1100px}"
       "table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;padding:3px 7px;text-align:right}"
       "td.l,th.l{text-align:left}code{background:#f4f4f4;padding:1px 4px}</style></head><body>";
  o << "<h1>Design search: " << esc(pr.name) << "</h1>";
  o << "<p>Problem <code>" << esc(pr.file) << "</code>, base scene <code>" << esc(pr.scene_file) << "</code>, "
    << (pr.exhaustive ? "exhaustive search" : "pagmo sga") << ", population " << pr.ga.population << ", seed "
    << pr.ga.seed << ". Objective: " << (pr.objective.maximize ? "maximize " : "minimize ");
  for (size_t k = 0; k < pr.objective.weights.size(); ++k)
    o << (k ? " + " : "") << shown_num(pr.objective.weights[k].second) << " &times; "
      << esc(pr.measures[static_cast<size_t>(pr.objective.weights[k].first)].name);
  o << "; a failed run scores " << shown_num(pr.objective.failed_fitness) << ".</p>";
  if (best.valid)
    o << "<h2>Best</h2><p><b><code>" << esc(best.key) << "</code></b>, fitness in the search "
      << shown_num(best.fitness, 10) << (best.failed ? " (failed)" : "") << ", found in generation " << best.generation
      << " (island " << best.island << ", individual " << best.individual << "). " << esc(notes.replay) << "</p>";
  for (const std::string* t : {&notes.trials, &notes.noise})
    if (!t->empty()) o << "<p>" << (t == &notes.noise ? "<b>Warning:</b> " : "") << esc(*t) << ".</p>";
  if (const Verification* v = notes.verification) {
    o << "<h2>Verification</h2><p>Each of the best " << v->leaders.size() << " distinct individuals run again with "
      << v->fresh_trials << " fresh seeds the search never used";
    bool exact = false, pic = false;
    for (const auto& l : v->leaders) {
      exact |= l.has_exact;
      pic |= l.has_pic;
    }
    if (exact) o << ", the same with the converged solver (<code>physics.solver: exact</code>)";
    if (pic) o << ", and once on the board's own binaries (<code>--target pic</code>)";
    o << (v->best >= 0 ? ". best.yaml is the best of them with fresh seeds."
                       : ". None passed both in the search and with fresh seeds: best.yaml stays the search's best.")
      << "</p><table><tr><th class='l'>genome</th><th>search</th>"
         "<th>fresh seeds</th><th>fresh min .. max</th>"
      << (exact ? "<th>exact solver</th>" : "") << (pic ? "<th>board</th>" : "") << "<th class='l'>flags</th></tr>";
    auto cell = [&](const EvalResult& r) {
      if (r.failed) return "<td class='l'>fails: " + esc(r.why) + "</td>";
      std::string t = shown_num(r.fitness, 6);
      if (r.trials > 1 && std::isfinite(r.fitness_sd)) t += " &plusmn; " + shown_num(r.fitness_sd, 3);
      return "<td>" + t + " (" + std::to_string(r.trials) + ")</td>";
    };
    for (size_t l = 0; l < v->leaders.size(); ++l) {
      const VerifiedLeader& x = v->leaders[l];
      o << "<tr><td class='l'><code>" << esc(x.search.genome) << "</code>"
        << (static_cast<int>(l) == v->best ? " <b>(verified best)</b>" : "") << "</td>" << cell(x.search.result)
        << cell(x.fresh) << "<td>" << shown_num(x.fresh.fitness_min, 6) << " .. " << shown_num(x.fresh.fitness_max, 6)
        << "</td>";
      if (exact) o << (x.has_exact ? cell(x.exact) : "<td></td>");
      if (pic) o << (x.has_pic ? cell(x.pic) : "<td></td>");
      std::string flags;
      for (const auto& f : x.flags) flags += (flags.empty() ? "" : "; ") + f;
      o << "<td class='l'" << (flags.empty() ? "" : " style='color:#b00'") << ">" << esc(flags) << "</td></tr>";
    }
    o << "</table>";
  }
  if (!notes.verification_note.empty()) o << "<p>" << esc(notes.verification_note) << "</p>";
  o << "<h2>Fitness per generation</h2>" << plot_svg(pr, st);

  // the best distinct individuals
  std::vector<const HistoryRow*> distinct;
  std::set<std::string> seen;
  for (const auto& r : rows)
    if (seen.insert(r.genome).second) distinct.push_back(&r);
  std::stable_sort(distinct.begin(), distinct.end(), [&](const HistoryRow* a, const HistoryRow* b) {
    if (a->result.failed != b->result.failed) return !a->result.failed;
    return better_fitness(pr.objective, a->result.fitness, b->result.fitness);
  });
  o << "<h2>Best individuals</h2><table><tr><th class='l'>genome</th><th>fitness</th><th>trials</th><th>sd</th>"
       "<th>min .. max</th>";
  for (const auto& m : pr.measures) o << "<th>" << esc(m.name) << "</th>";
  o << "<th>first seen</th><th class='l'>fault or why</th></tr>";
  for (size_t i = 0; i < distinct.size() && i < 15; ++i) {
    const HistoryRow& r = *distinct[i];
    o << "<tr><td class='l'><code>" << esc(r.genome) << "</code></td><td>" << shown_num(r.result.fitness, 6) << "</td><td>"
      << r.result.trials << "</td><td>" << shown_num(r.result.fitness_sd, 3) << "</td><td>"
      << shown_num(r.result.fitness_min, 6) << " .. " << shown_num(r.result.fitness_max, 6) << "</td>";
    for (double m : r.result.measures) o << "<td>" << shown_num(m) << "</td>";
    o << "<td>gen " << r.generation << (pr.ga.islands > 1 ? " island " + std::to_string(r.island) : std::string())
      << " #" << r.individual << "</td><td class='l'>" << esc(r.result.why)
      << (r.result.early_stop.empty() ? "" : (r.result.why.empty() ? "" : "; ") + esc(r.result.early_stop))
      << "</td></tr>";
  }
  o << "</table><p>" << distinct.size() << " distinct individuals in " << rows.size() << " evaluations.</p>";

  o << "<h2>Generations</h2><table><tr><th>generation</th><th>best</th><th>mean</th><th>worst</th>"
       "<th>failed</th><th>cache hits</th><th>simulation wall s</th></tr>";
  for (const auto& s : st)
    o << "<tr><td>" << s.generation << "</td><td>" << shown_num(s.best) << "</td><td>" << shown_num(s.mean) << "</td><td>"
      << shown_num(s.worst) << "</td><td>" << s.failed << "</td><td>" << s.cached << "</td><td>" << shown_fixed(s.wall_s, 1)
      << "</td></tr>";
  o << "</table>";
  if (!replay_html.empty())
    o << "<h2>The best run</h2><p>The replay of <code>best.yaml</code> (the viewer of <code>chainsim view</code>).</p>"
         "<iframe style='width:100%;height:640px;border:1px solid #ccc' srcdoc=\""
      << esc(replay_html) << "\"></iframe>";
  o << "</body></html>\n";
  return o.str();
}

}  // namespace chainsim
