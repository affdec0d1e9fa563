#include "testing/evaluate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>

#include "testing/motion.h"
#include "output/run_reader.h"
#include "text/number_text.h"

namespace chainsim {
namespace {

std::string at_time(double t) {
  char b[32];
  std::snprintf(b, sizeof b, "at %.3f s", t);
  return b;
}

CheckResult compared(const Comparison& c, double v, double t) {
  CheckResult r;
  r.value = v;
  r.pass = c.holds(v);
  r.measured = general_text(v);
  r.t_s = t;
  return r;
}

// the numeric leaves of a JSON value as dotted paths (for an error message)
void numeric_paths(const nlohmann::json& j, const std::string& pre, std::vector<std::string>* out) {
  if (j.is_number()) out->push_back(pre);
  else if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it) numeric_paths(*it, pre.empty() ? it.key() : pre + "." + it.key(), out);
  else if (j.is_array())
    for (size_t i = 0; i < j.size(); ++i) numeric_paths(j[i], pre + "." + std::to_string(i), out);
}

CheckResult summary_value(const Expectation& e, RunReader& run) {
  const nlohmann::json* j = &run.summary();
  size_t b = 0;
  for (;;) {
    const size_t dot = e.path.find('.', b);
    const std::string seg = e.path.substr(b, dot == std::string::npos ? std::string::npos : dot - b);
    const nlohmann::json* next = nullptr;
    if (j->is_object() && j->contains(seg)) {
      next = &(*j)[seg];
    } else if (j->is_array() && !seg.empty() && seg.find_first_not_of("0123456789") == std::string::npos &&
               std::strtoul(seg.c_str(), nullptr, 10) < j->size()) {
      next = &(*j)[std::strtoul(seg.c_str(), nullptr, 10)];
    }
    if (!next) {
      std::vector<std::string> known;
      numeric_paths(run.summary(), "", &known);
      std::string list;
      for (size_t i = 0; i < known.size() && i < 24; ++i) list += (i ? ", " : "") + known[i];
      if (known.size() > 24) list += ", ...";
      throw EvaluationError("unknown metric '" + e.path + "': summary.json has no '" + seg + "' there (numbers: " + list + ")");
    }
    j = next;
    if (dot == std::string::npos) break;
    b = dot + 1;
  }
  if (j->is_boolean()) return compared(e.cmp, j->get<bool>() ? 1 : 0, run.end_s());
  if (!j->is_number())
    throw EvaluationError("'" + e.path + "' in summary.json is not a number (" + std::string(j->type_name()) + ")");
  return compared(e.cmp, j->get<double>(), run.end_s());
}

const std::vector<double>& trace_column(const Expectation& e, RunReader& run) {
  if (const auto* c = run.trace_column(e.path)) return *c;
  // name the columns of the same module (or the first ones)
  const size_t dot = e.path.find('.');
  const std::string pre = dot == std::string::npos ? "" : e.path.substr(0, dot + 1);
  std::string list;
  int n = 0;
  for (const std::string& c : run.trace_columns())
    if (!pre.empty() && c.rfind(pre, 0) == 0 && n++ < 40) list += (list.empty() ? "" : ", ") + c;
  if (list.empty())
    for (const std::string& c : run.trace_columns())
      if (n++ < 12) list += (list.empty() ? "" : ", ") + c;
  throw EvaluationError("unknown trace column '" + e.path + "' (" + (pre.empty() || n == 0 ? "columns" : "columns of " + pre.substr(0, pre.size() - 1)) +
                        ": " + list + (n > 40 ? ", ..." : "") + ")");
}

CheckResult trace_stat(const Expectation& e, RunReader& run) {
  const auto& v = trace_column(e, run);
  const auto& t = run.trace_time();
  if (v.empty()) return {false, "the trace has no rows", NAN, run.end_s()};
  switch (e.stat) {
    case Expectation::Stat::final_value: return compared(e.cmp, v.back(), t.back());
    case Expectation::Stat::max:
    case Expectation::Stat::min: {
      size_t k = 0;
      for (size_t i = 1; i < v.size(); ++i)
        if (e.stat == Expectation::Stat::max ? v[i] > v[k] : v[i] < v[k]) k = i;
      CheckResult r = compared(e.cmp, v[k], t[k]);
      r.measured += " (" + at_time(t[k]) + ")";
      return r;
    }
    case Expectation::Stat::mean: {
      double s = 0;
      for (double x : v) s += x;
      return compared(e.cmp, s / v.size(), t.back());
    }
    case Expectation::Stat::at: {
      if (e.at_s > t.back() + 1e-9) return {false, "the trace ends at " + general_text(t.back()) + " s", NAN, t.back()};
      size_t k = 0;
      while (k + 1 < t.size() && t[k + 1] <= e.at_s + 1e-9) ++k;
      return compared(e.cmp, v[k], t[k]);
    }
  }
  return {};
}

// the first event time and the count, judged by the timing
CheckResult timed(const Timing& tm, double first_t, int count, const std::string& what_first, double end_s) {
  CheckResult r;
  const bool seen = count > 0;
  switch (tm.mode) {
    case Timing::Mode::before:
      r.pass = seen && first_t <= tm.t_s + 1e-9;
      r.t_s = seen ? first_t : std::min(tm.t_s, end_s);
      break;
    case Timing::Mode::after:
      r.pass = seen && first_t >= tm.t_s - 1e-9;
      r.t_s = seen ? first_t : end_s;
      break;
    case Timing::Mode::never:
      r.pass = !seen;
      r.t_s = seen ? first_t : end_s;
      break;
    case Timing::Mode::count:
      r.pass = tm.count.holds(count);
      r.value = count;
      r.measured = std::to_string(count);
      r.t_s = end_s;
      return r;
  }
  if (seen) {
    r.value = first_t;
    r.measured = at_time(first_t) + what_first;
  } else {
    r.measured = "never (run ended at " + general_text(end_s) + " s)";
  }
  return r;
}

CheckResult trace_when(const Expectation& e, RunReader& run) {
  const auto& v = trace_column(e, run);
  const auto& t = run.trace_time();
  for (size_t i = 0; i < v.size(); ++i)
    if (e.cmp.holds(v[i])) return timed(e.timing, t[i], 1, " (value " + general_text(v[i]) + ")", run.end_s());
  return timed(e.timing, 0, 0, "", run.end_s());
}

int endpoint(const EndpointName& who, RunReader& run) {
  const int n = run.module_count();
  if (!who.central && who.module >= n)
    throw EvaluationError(who.text() + ": the chain has " + std::to_string(n) + " modules (m0.." +
                          "m" + std::to_string(n - 1) + ")");
  return run.endpoint_index(who.central, who.module);
}

CheckResult log_match(const Expectation& e, RunReader& run) {
  const auto& lines = run.log(endpoint(e.who, run));
  double first = 0;
  std::string first_text;
  int count = 0;
  for (size_t i = 0; i < lines.size(); ++i) {
    run.poll_stop(i);
    if (pattern_found(e, lines[i].text) && count++ == 0) first = lines[i].t_s, first_text = lines[i].text;
  }
  if (first_text.size() > 60) first_text = first_text.substr(0, 57) + "...";
  return timed(e.timing, first, count, ": \"" + first_text + "\"", run.end_s());
}

bool field_is(const BusEvent& ev, const char* key, long want, int base) {
  const auto it = ev.field.find(key);
  return it != ev.field.end() && std::strtol(it->second.c_str(), nullptr, base) == want;
}

CheckResult bus_match(const Expectation& e, RunReader& run, const std::string& event,
                      const std::function<bool(const BusEvent&)>& match) {
  double first = 0;
  int count = 0;
  const auto& events = run.bus();
  for (size_t i = 0; i < events.size(); ++i) {
    run.poll_stop(i);
    if (events[i].event == event && match(events[i]) && count++ == 0) first = events[i].t_us * 1e-6;
  }
  return timed(e.timing, first, count, "", run.end_s());
}

CheckResult bus(const Expectation& e, RunReader& run) {
  if (e.event == "i2c" || e.event == "i2c-drop") {
    const int from = e.from ? endpoint(*e.from, run) : -1;
    return bus_match(e, run, e.event, [&](const BusEvent& ev) {
      if (from >= 0 && !field_is(ev, "from", from, 10)) return false;
      if (e.address && !field_is(ev, "to", *e.address, 16)) return false;
      if (!e.data_prefix.empty()) {
        const auto it = ev.field.find("data");
        if (it == ev.field.end() || it->second.rfind(e.data_prefix, 0) != 0) return false;
      }
      return true;
    });
  }
  const int who = endpoint(e.who, run);
  if (e.event == "addr")
    return bus_match(e, run, "addr", [&](const BusEvent& ev) {
      return field_is(ev, "endpoint", who, 10) && (!e.address || field_is(ev, "address", *e.address, 16));
    });
  // sout: the sync lines' "sync endpoint=E sout=L"
  return bus_match(e, run, "sync", [&](const BusEvent& ev) {
    return field_is(ev, "endpoint", who, 10) && (!e.level || field_is(ev, "sout", *e.level, 10));
  });
}

CheckResult no_faults(RunReader& run) {
  CheckResult r;
  int n = 0;
  std::string first;
  for (const auto& m : run.summary().value("modules", nlohmann::json::array()))
    if (m.contains("fault") && m["fault"].is_string()) {
      if (n++ == 0) first = m["fault"].get<std::string>();
    }
  r.pass = n == 0;
  r.value = n;
  r.t_s = run.end_s();
  if (n == 0) {
    r.measured = "0 faults";
    return r;
  }
  r.measured = std::to_string(n) + (n == 1 ? " fault: " : " faults, the first: ") + first;
  for (const BusEvent& ev : run.bus())
    if (ev.event == "fault") {
      r.t_s = ev.t_us * 1e-6;
      break;
    }
  return r;
}

}  // namespace

CheckResult evaluate(const Expectation& e, RunReader& run) {
  try {
    switch (e.kind) {
      case Expectation::Kind::no_faults: return no_faults(run);
      case Expectation::Kind::summary: return summary_value(e, run);
      case Expectation::Kind::motion:
        try {
          return compared(e.cmp, motion_metric(run, e.path), run.end_s());
        } catch (const MotionError& x) {
          if (x.unknown) throw EvaluationError(x.what());
          return {false, std::string("cannot be measured: ") + x.what(), NAN, run.end_s()};
        }
      case Expectation::Kind::trace_stat: return trace_stat(e, run);
      case Expectation::Kind::trace_when: return trace_when(e, run);
      case Expectation::Kind::log: return log_match(e, run);
      case Expectation::Kind::bus: return bus(e, run);
      case Expectation::Kind::touch: {
        const int who = endpoint(e.who, run);
        return bus_match(e, run, "touch", [&](const BusEvent& ev) {
          return field_is(ev, "endpoint", who, 10) && field_is(ev, "level", 1, 10);
        });
      }
    }
  } catch (const RunReadError& x) {
    return {false, std::string("cannot be measured: ") + x.what(), NAN, -1};
  }
  return {};
}

}  // namespace chainsim
