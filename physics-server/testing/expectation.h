// One line of a test file's `expect:` list, parsed: what to measure in a
// finished run directory and what it must be. The grammar and every metric
// are in docs/testing.md; evaluate.h measures them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace re2 {
class RE2;
}

namespace chainsim {

// a syntax error; offset is the character of the expectation text at fault
struct ExpectationError : std::runtime_error {
  ExpectationError(size_t at, const std::string& what) : std::runtime_error(what), offset(at) {}
  size_t offset;
};

// a value comparison: `< 3`, `>= 0.2`, `between -1 and 1` (inclusive)
struct Comparison {
  enum class Op { lt, le, gt, ge, eq, ne, between };
  Op op = Op::lt;
  double a = 0, b = 0;  // b: the upper bound of between
  bool holds(double v) const;
  std::string text() const;  // as it would be written, e.g. ">= 0.2"
};

// when an event must happen: `before T` (first one at t <= T), `after T`
// (first one at t >= T), `never`, or `count <comparison>`
struct Timing {
  enum class Mode { before, after, never, count };
  Mode mode = Mode::before;
  double t_s = 0;
  Comparison count;
};

// a run's endpoint: module k (`m<k>`) or the central control (`central`)
struct EndpointName {
  bool central = false;
  int module = 0;
  std::string text() const { return central ? "central" : "m" + std::to_string(module); }
};

struct Expectation {
  enum class Kind {
    no_faults,   // no module faulted
    summary,     // a number of summary.json by its dotted path
    motion,      // a chain motion metric computed from trace.csv (motion.h)
    trace_stat,  // trace.<column> final|max|min|mean|at T <comparison>
    trace_when,  // trace.<column> <comparison> <timing>: the first row where it holds
    log,         // log <endpoint> /regex/ <timing>
    bus,         // bus <event> [filters] <timing>
    touch,       // touch <endpoint> <timing>: the module's touch input closing
  };
  enum class Stat { final_value, max, min, mean, at };

  std::string text;  // as written in the test file
  Kind kind = Kind::no_faults;
  std::string path;  // summary path, motion metric or trace column
  Stat stat = Stat::final_value;
  double at_s = 0;   // Stat::at
  Comparison cmp;    // summary, motion, trace_stat, trace_when
  Timing timing;     // trace_when, log, bus, touch

  EndpointName who;             // log, touch; bus addr/sout
  std::string pattern;      // log: the pattern as written, '\/' read as '/'
  // log: the pattern compiled by RE2, which matches in time linear in the
  // line; shared, as RE2 cannot be copied
  std::shared_ptr<const re2::RE2> regex;
  std::string event;        // bus: i2c, i2c-drop, addr, sout
  std::optional<EndpointName> from;  // bus i2c, i2c-drop: sender
  std::optional<int> address;    // bus i2c, i2c-drop: `to`; addr: the address taken
  std::string data_prefix;       // bus i2c: `data` hex prefix, lower case
  std::optional<int> level;      // bus sout: 0 or 1
};

// parses one expectation; throws ExpectationError
Expectation parse_expectation(const std::string& text);

// does a log pattern (Expectation::regex) match anywhere in line?
bool pattern_found(const Expectation& e, const std::string& line);

}  // namespace chainsim
