// Two runs compared. See run_compare.h.
#include "testing/run_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "text/number_text.h"

namespace chainsim {
namespace {

constexpr double kNone = -1;

double earliest(const Divergence& d) {
  const double inf = std::numeric_limits<double>::infinity();
  return std::min(d.t_a < 0 ? inf : d.t_a, d.t_b < 0 ? inf : d.t_b);
}

// one channel's events in time order
struct Item {
  double t;
  std::string value;
};

// the first index where two sequences differ, within the span both runs cover
// (cut: a later item of one run, the other's run having ended, is no divergence)
void walk(const std::vector<Item>& a, const std::vector<Item>& b, double cut, const std::string& channel,
          double time_tol, EndpointComparison* ec) {
  ChannelTally tally{channel, 0, false};
  for (size_t i = 0;; ++i) {
    const bool has_a = i < a.size() && (a[i].t < cut || i < b.size());
    const bool has_b = i < b.size() && (b[i].t < cut || i < a.size());
    if (!has_a && !has_b) break;
    Divergence d{ec->endpoint, ec->who, channel, has_a ? a[i].t : kNone, has_b ? b[i].t : kNone,
                 has_a ? a[i].value : "(none)", has_b ? b[i].value : "(none)"};
    if (!has_a || !has_b || a[i].value != b[i].value || (time_tol > 0 && std::fabs(a[i].t - b[i].t) > time_tol)) {
      ec->divergences.push_back(d);
      tally.diverged = true;
      break;
    }
    ++tally.compared;
  }
  ec->tally.push_back(tally);
}

// the servo set-point columns of module m: (column, tolerance)
std::vector<std::pair<std::string, double>> setpoint_columns(RunReader& r, int m, const CompareTolerances& tol) {
  std::vector<std::pair<std::string, double>> out;
  const std::string prefix = "m" + std::to_string(m) + ".s";
  for (const std::string& c : r.trace_columns()) {
    if (c.rfind(prefix, 0) != 0) continue;
    if (c.ends_with(".setpoint_deg")) out.emplace_back(c, tol.setpoint_deg);
    else if (c.ends_with(".setpoint_mm")) out.emplace_back(c, tol.setpoint_mm);
    else if (c.ends_with(".command")) out.emplace_back(c, tol.command);
  }
  return out;
}

// a set-point column: the first row where either run's value has no match
// in the other's within the lag window
void compare_setpoint(RunReader& a, RunReader& b, const std::string& col, double tol, double cut,
                      const CompareTolerances& t, EndpointComparison* ec) {
  const std::string channel = "setpoint " + col.substr(0, col.rfind('.'));
  const auto* va = a.trace_column(col);
  const auto* vb = b.trace_column(col);
  if (!va || !vb) return;
  const auto& ta = a.trace_time();
  const auto& tb = b.trace_time();
  const size_t n = std::min({va->size(), vb->size(), ta.size(), tb.size()});
  ChannelTally tally{channel, 0, false};
  auto matched = [&](const std::vector<double>& x, const std::vector<double>& y, size_t j) {
    for (size_t k = j; k-- > 0 && ta[j] - ta[k] <= t.setpoint_lag_s + 1e-9;)
      if (std::fabs(x[j] - y[k]) <= tol) return true;
    for (size_t k = j; k < n && ta[k] - ta[j] <= t.setpoint_lag_s + 1e-9; ++k)
      if (std::fabs(x[j] - y[k]) <= tol) return true;
    return false;
  };
  for (size_t j = 0; j < n && ta[j] < cut; ++j) {
    if (std::fabs(ta[j] - tb[j]) > 1e-9) break;  // traces at different rates: rows no longer line up
    if (!matched(*va, *vb, j) || !matched(*vb, *va, j)) {
      const int digits = col.ends_with(".command") ? 4 : 3;
      ec->divergences.push_back({ec->endpoint, ec->who, channel, ta[j], tb[j], fixed_text((*va)[j], digits),
                                 fixed_text((*vb)[j], digits)});
      tally.diverged = true;
      break;
    }
    ++tally.compared;
  }
  ec->tally.push_back(tally);
}

// the shift of b's column against a's that fits best, within max_rows rows:
// of the shifts that fit nearly as well as the best (a periodic gait fits
// every period), the smallest
SetpointLag best_lag(const std::string& col, const std::vector<double>& a, const std::vector<double>& b, size_t rows,
                     long max_rows, double dt) {
  SetpointLag out{col, 0, 0, 0};
  std::vector<std::pair<long, double>> fits;
  double best = std::numeric_limits<double>::infinity();
  for (long lag = -max_rows; lag <= max_rows; ++lag) {
    double s = 0;
    size_t n = 0;
    for (size_t j = 0; j < rows; ++j) {
      const long k = static_cast<long>(j) + lag;
      if (k < 0 || k >= static_cast<long>(rows)) continue;
      s += (b[static_cast<size_t>(k)] - a[j]) * (b[static_cast<size_t>(k)] - a[j]);
      ++n;
    }
    if (n < rows / 2 || n == 0) continue;  // too little overlap to judge
    const double rms = std::sqrt(s / static_cast<double>(n));
    if (lag == 0) out.rms_unshifted = rms;
    fits.emplace_back(lag, rms);
    best = std::min(best, rms);
  }
  long chosen = max_rows + 1;
  for (const auto& [lag, rms] : fits) {
    if (rms > 1.5 * best + 1e-9 || std::labs(lag) >= std::labs(chosen)) continue;
    chosen = lag;
    out.rms = rms;
  }
  out.lag_s = chosen <= max_rows ? static_cast<double>(chosen) * dt : 0.0;
  return out;
}

// the time of the fault bus.log records for an endpoint named who
double fault_time(RunReader& r, const std::string& name_prefix) {
  for (const BusEvent& e : r.bus())
    if (e.event == "fault" && e.text.rfind(name_prefix, 0) == 0) return static_cast<double>(e.t_us) * 1e-6;
  return r.end_s();
}

std::string value_or(const nlohmann::json& j, const char* key, const std::string& none) {
  if (!j.contains(key) || j[key].is_null()) return none;
  return j[key].is_string() ? j[key].get<std::string>() : j[key].dump();
}

}  // namespace

const Divergence* CompareReport::first() const {
  const Divergence* best = nullptr;
  for (const auto& e : endpoints)
    for (const auto& d : e.divergences)
      if (!best || earliest(d) < earliest(*best)) best = &d;
  return best;
}

CompareReport compare_runs(RunReader& a, RunReader& b, const std::string& label_a, const std::string& label_b,
                           const CompareTolerances& tol) {
  CompareReport r;
  r.label_a = label_a;
  r.label_b = label_b;
  r.tol = tol;
  const auto& sa = a.summary();
  const auto& sb = b.summary();
  r.scene = value_or(sa, "scene", "?");
  r.end_a_s = a.end_s();
  r.end_b_s = b.end_s();
  r.exit_a = sa.value("exit_code", 0);
  r.exit_b = sb.value("exit_code", 0);
  r.rtf_a = sa.value("real_time_factor", 0.0);
  r.rtf_b = sb.value("real_time_factor", 0.0);
  r.distance_a_m = sa.contains("chain") ? sa["chain"].value("distance_m", 0.0) : 0.0;
  r.distance_b_m = sb.contains("chain") ? sb["chain"].value("distance_m", 0.0) : 0.0;
  const double cut = std::min(r.end_a_s, r.end_b_s) - tol.end_slack_s;

  const auto& ma = sa.value("modules", nlohmann::json::array());
  const auto& mb = sb.value("modules", nlohmann::json::array());
  const size_t n = std::min(ma.size(), mb.size());
  const int modules = a.module_count();
  for (size_t e = 0; e < n; ++e) {
    EndpointComparison ec;
    ec.endpoint = static_cast<int>(e);
    const bool central = static_cast<int>(e) == modules;
    const std::string type = value_or(ma[e], "type", "?");
    const std::string name = central ? "central control (" : "module " + std::to_string(e) + " (";
    ec.who = name + type + ")";
    const int ep = static_cast<int>(e);

    auto logs = [&](RunReader& r) {
      std::vector<Item> out;
      for (const LogLine& l : r.log(ep)) out.push_back({l.t_s, l.text});
      return out;
    };
    walk(logs(a), logs(b), cut, "log", 0, &ec);

    auto frames = [&](RunReader& r) {
      std::vector<Item> out;
      for (const BusEvent& ev : r.bus()) {
        if (ev.event != "i2c") continue;
        const auto f = ev.field.find("from");
        if (f == ev.field.end() || f->second != std::to_string(ep)) continue;
        const auto to = ev.field.find("to");
        const auto data = ev.field.find("data");
        out.push_back({static_cast<double>(ev.t_us) * 1e-6, "to " + (to == ev.field.end() ? "?" : to->second) +
                                                                 " data " + (data == ev.field.end() ? "?" : data->second)});
      }
      return out;
    };
    walk(frames(a), frames(b), cut, "i2c", 0, &ec);

    auto edges = [&](RunReader& r) {
      std::vector<Item> out;
      for (const BusEvent& ev : r.bus()) {
        if (ev.event != "sync") continue;
        const auto f = ev.field.find("endpoint");
        if (f == ev.field.end() || f->second != std::to_string(ep)) continue;
        const auto s = ev.field.find("sout");
        out.push_back({static_cast<double>(ev.t_us) * 1e-6, s != ev.field.end() && s->second == "1" ? "rose" : "fell"});
      }
      return out;
    };
    walk(edges(a), edges(b), cut, "sout", tol.sout_s, &ec);

    if (!central)
      for (const auto& [col, t] : setpoint_columns(a, ep, tol)) compare_setpoint(a, b, col, t, cut, tol, &ec);

    const std::string fa = value_or(ma[e], "fault", ""), fb = value_or(mb[e], "fault", "");
    if (fa.empty() != fb.empty()) {
      const std::string prefix = central ? "central control (" + type : "module " + std::to_string(e) + " (" + type;
      ec.divergences.push_back({ep, ec.who, "fault", fa.empty() ? kNone : fault_time(a, prefix),
                                fb.empty() ? kNone : fault_time(b, prefix), fa.empty() ? "(none)" : fa,
                                fb.empty() ? "(none)" : fb});
    }
    const std::string aa = value_or(ma[e], "i2c_address", "(none)"), ab = value_or(mb[e], "i2c_address", "(none)");
    if (aa != ab)
      ec.divergences.push_back({ep, ec.who, "address", ma[e].value("addressed_at_s", -1.0),
                                mb[e].value("addressed_at_s", -1.0), aa, ab});
    std::stable_sort(ec.divergences.begin(), ec.divergences.end(),
                     [](const Divergence& x, const Divergence& y) { return earliest(x) < earliest(y); });
    r.endpoints.push_back(std::move(ec));
  }

  // drift: module 0's first body, and every rotary servo's measured angle
  const auto& ta = a.trace_time();
  const auto& tb = b.trace_time();
  const std::string head = a.body_columns(0).empty() ? "" : a.body_columns(0).front();
  size_t rows = std::min(ta.size(), tb.size());
  while (rows > 0 && std::fabs(ta[rows - 1] - tb[rows - 1]) > 1e-9) --rows;
  if (!head.empty() && rows > 0) {
    const auto *xa = a.trace_column(head + ".x"), *ya = a.trace_column(head + ".y"), *za = a.trace_column(head + ".z");
    const auto *xb = b.trace_column(head + ".x"), *yb = b.trace_column(head + ".y"), *zb = b.trace_column(head + ".z");
    if (xa && ya && za && xb && yb && zb) {
      for (size_t j = 0; j < rows; ++j) {
        const double d = std::hypot((*xa)[j] - (*xb)[j], (*ya)[j] - (*yb)[j], (*za)[j] - (*zb)[j]);
        if (d > r.head_apart_max_m) {
          r.head_apart_max_m = d;
          r.head_apart_max_at_s = ta[j];
        }
        r.head_apart_end_m = d;
      }
    }
  }
  double sum = 0;
  size_t count = 0;
  for (const std::string& c : a.trace_columns()) {
    if (!c.ends_with(".angle_deg")) continue;
    const auto* va = a.trace_column(c);
    const auto* vb = b.trace_column(c);
    if (!va || !vb) continue;
    double s = 0;
    for (size_t j = 0; j < rows; ++j) s += ((*va)[j] - (*vb)[j]) * ((*va)[j] - (*vb)[j]);
    sum += s;
    count += rows;
    const double rms = rows ? std::sqrt(s / static_cast<double>(rows)) : 0.0;
    if (rms > r.angle_worst_rms_deg) {
      r.angle_worst_rms_deg = rms;
      r.angle_worst = c;
    }
  }
  r.angle_rms_deg = count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
  if (rows > 2) {
    const double dt = ta[1] - ta[0];
    const long max_rows = dt > 0 ? std::lround(1.0 / dt) : 0;
    for (int m = 0; m < modules; ++m)
      for (const auto& [col, t] : setpoint_columns(a, m, tol)) {
        const auto* va = a.trace_column(col);
        const auto* vb = b.trace_column(col);
        if (!va || !vb) continue;
        // a set-point that stays put fits every shift: nothing to learn from it
        const auto [lo, hi] = std::minmax_element(va->begin(), va->begin() + static_cast<long>(rows));
        if (*hi - *lo > 2 * t) r.lags.push_back(best_lag(col, *va, *vb, rows, max_rows, dt));
      }
  }
  return r;
}

std::string compare_text(const CompareReport& r) {
  auto at = [](double t) { return t < 0 ? std::string("-") : fixed_text(t, 3); };
  std::string s = r.label_a + " against " + r.label_b + " (scene " + r.scene + ")\n";
  auto run = [&](const std::string& label, double end, int exit, double dist, double rtf) {
    return "  " + label + ": " + fixed_text(end, 3) + " s simulated, exit code " + std::to_string(exit) + ", chain moved " +
           fixed_text(dist, 4) + " m, " + fixed_text(rtf, 2) + "x real time\n";
  };
  s += run(r.label_a, r.end_a_s, r.exit_a, r.distance_a_m, r.rtf_a);
  s += run(r.label_b, r.end_b_s, r.exit_b, r.distance_b_m, r.rtf_b);
  s += "first divergence of each endpoint (times " + r.label_a + " / " + r.label_b + ", seconds):\n";
  for (const auto& e : r.endpoints) {
    std::string agreed;
    for (const auto& t : e.tally) {
      if (t.channel.rfind("setpoint", 0) == 0 && !t.diverged && t.compared == 0) continue;
      agreed += (agreed.empty() ? "" : ", ") + t.channel + " " + std::to_string(t.compared);
    }
    if (e.divergences.empty()) {
      s += "  " + e.who + ": none (agree: " + agreed + ")\n";
      continue;
    }
    const Divergence& d = e.divergences.front();
    s += "  " + e.who + ": " + d.channel + " at " + at(d.t_a) + " / " + at(d.t_b) + ": " + r.label_a + " \"" + d.a +
         "\", " + r.label_b + " \"" + d.b + "\"\n";
    s += "      (agree before it: " + agreed + ")\n";
    for (size_t i = 1; i < e.divergences.size(); ++i) {
      const Divergence& o = e.divergences[i];
      s += "      then " + o.channel + " at " + at(o.t_a) + " / " + at(o.t_b) + ": \"" + o.a + "\", \"" + o.b + "\"\n";
    }
  }
  s += "drift: module 0's head " + fixed_text(r.head_apart_end_m * 1000, 2) + " mm apart at the end (most " +
       fixed_text(r.head_apart_max_m * 1000, 2) + " mm, at t=" + fixed_text(r.head_apart_max_at_s, 2) +
       " s); measured servo angles differ by " + fixed_text(r.angle_rms_deg, 3) + " degrees RMS" +
       (r.angle_worst.empty() ? "" : " (most: " + r.angle_worst + ", " + fixed_text(r.angle_worst_rms_deg, 3) + ")") + "\n";
  if (!r.lags.empty()) {
    std::vector<double> shifts;
    const SetpointLag* worst = &r.lags.front();
    for (const auto& l : r.lags) {
      shifts.push_back(l.lag_s);
      if (l.rms > worst->rms) worst = &l;
    }
    std::sort(shifts.begin(), shifts.end());
    s += "set-points that move: " + r.label_b + "'s follow " + r.label_a + "'s " + fixed_text(shifts[shifts.size() / 2] * 1000, 0) +
         " ms later (median of " + std::to_string(shifts.size()) + " servos, from " +
         fixed_text(shifts.front() * 1000, 0) + " to " + fixed_text(shifts.back() * 1000, 0) +
         " ms); shifted so, they differ by at most " + fixed_text(worst->rms, 3) + " RMS (" + worst->column + ")\n";
  }
  s += "tolerances: set-points " + fixed_text(r.tol.setpoint_deg, 3) + " degrees, " + fixed_text(r.tol.setpoint_mm, 3) +
       " mm, " + fixed_text(r.tol.command, 4) + " of a command, within " + fixed_text(r.tol.setpoint_lag_s * 1000, 0) +
       " ms; Sout edges within " + fixed_text(r.tol.sout_s * 1000, 0) + " ms; the last " +
       fixed_text(r.tol.end_slack_s * 1000, 0) + " ms of the shorter run are not compared\n";
  return s;
}

std::vector<Target> parse_compare_targets(const std::string& text, std::string* error) {
  std::vector<Target> out;
  size_t b = 0;
  for (;;) {
    const size_t e = std::min(text.find(',', b), text.size());
    const std::string t = text.substr(b, e - b);
    if (t != "native" && t != "pic") {
      *error = "--compare " + text + ": two targets, native and pic, separated by a comma (e.g. native,pic)";
      return {};
    }
    out.push_back(t == "pic" ? Target::Pic : Target::Native);
    if (e == text.size()) break;
    b = e + 1;
  }
  if (out.size() != 2 || out[0] == out[1]) {
    *error = "--compare " + text + ": two different targets, e.g. native,pic";
    return {};
  }
  return out;
}

nlohmann::json compare_json(const CompareReport& r) {
  auto div = [](const Divergence& d) {
    return nlohmann::json{{"endpoint", d.endpoint}, {"who", d.who}, {"channel", d.channel},
                          {"t_a_s", d.t_a < 0 ? nlohmann::json(nullptr) : nlohmann::json(d.t_a)},
                          {"t_b_s", d.t_b < 0 ? nlohmann::json(nullptr) : nlohmann::json(d.t_b)},
                          {"a", d.a}, {"b", d.b}};
  };
  nlohmann::json eps = nlohmann::json::array();
  for (const auto& e : r.endpoints) {
    nlohmann::json divs = nlohmann::json::array(), tally = nlohmann::json::object();
    for (const auto& d : e.divergences) divs.push_back(div(d));
    for (const auto& t : e.tally) tally[t.channel] = {{"agreed", t.compared}, {"diverged", t.diverged}};
    eps.push_back({{"endpoint", e.endpoint}, {"who", e.who}, {"divergences", divs}, {"channels", tally}});
  }
  const Divergence* first = r.first();
  return {{"a", {{"label", r.label_a}, {"sim_time_s", r.end_a_s}, {"exit_code", r.exit_a},
                 {"distance_m", r.distance_a_m}, {"real_time_factor", r.rtf_a}}},
          {"b", {{"label", r.label_b}, {"sim_time_s", r.end_b_s}, {"exit_code", r.exit_b},
                 {"distance_m", r.distance_b_m}, {"real_time_factor", r.rtf_b}}},
          {"scene", r.scene},
          {"first", first ? div(*first) : nlohmann::json(nullptr)},
          {"endpoints", eps},
          {"drift", {{"head_apart_end_m", r.head_apart_end_m}, {"head_apart_max_m", r.head_apart_max_m},
                     {"head_apart_max_at_s", r.head_apart_max_at_s}, {"angle_rms_deg", r.angle_rms_deg},
                     {"angle_worst", r.angle_worst}, {"angle_worst_rms_deg", r.angle_worst_rms_deg}}},
          {"setpoint_lags", [&] {
             nlohmann::json l = nlohmann::json::array();
             for (const auto& x : r.lags)
               l.push_back({{"column", x.column}, {"lag_s", x.lag_s}, {"rms", x.rms}, {"rms_unshifted", x.rms_unshifted}});
             return l;
           }()},
          {"tolerances", {{"setpoint_lag_s", r.tol.setpoint_lag_s}, {"setpoint_deg", r.tol.setpoint_deg},
                          {"setpoint_mm", r.tol.setpoint_mm}, {"command", r.tol.command},
                          {"sout_s", r.tol.sout_s}, {"end_slack_s", r.tol.end_slack_s}}}};
}

}  // namespace chainsim
