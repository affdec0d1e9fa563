#include "testing/expectation.h"

#include <re2/re2.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace chainsim {
namespace {

struct Token {
  std::string text;
  size_t at = 0;
  bool regex = false;  // /.../, text without the slashes
  std::vector<size_t> src;  // a pattern: where each of its characters is in the expectation
};

// splits at blanks; /.../ is one token (a '\/' inside stays in the regex)
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < s.size()) {
    if (std::isspace(static_cast<unsigned char>(s[i]))) {
      ++i;
      continue;
    }
    Token t;
    t.at = i;
    if (s[i] == '/') {
      size_t j = i + 1;
      std::string re;
      while (j < s.size() && s[j] != '/') {
        t.src.push_back(j);
        if (s[j] == '\\' && j + 1 < s.size() && s[j + 1] == '/') {
          re += '/';
          j += 2;
          continue;
        }
        re += s[j++];
      }
      if (j >= s.size()) throw ExpectationError(i, "the pattern starting here has no closing '/'");
      t.text = re;
      t.regex = true;
      i = j + 1;
    } else {
      size_t j = i;
      while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      t.text = s.substr(i, j - i);
      i = j;
    }
    out.push_back(t);
  }
  return out;
}

class Parser {
 public:
  explicit Parser(const std::string& s) : s_(s), t_(tokenize(s)) {}

  bool done() const { return i_ >= t_.size(); }
  const Token* peek() const { return done() ? nullptr : &t_[i_]; }
  size_t here() const { return done() ? s_.size() : t_[i_].at; }
  [[noreturn]] void fail(const std::string& what) const { throw ExpectationError(here(), what); }
  [[noreturn]] void fail_at(const Token& t, const std::string& what) const { throw ExpectationError(t.at, what); }

  const Token& next(const std::string& what) {
    if (done()) fail("expected " + what + " here, the expectation ends");
    return t_[i_++];
  }
  bool accept(const std::string& word) {
    if (done() || t_[i_].regex || t_[i_].text != word) return false;
    ++i_;
    return true;
  }
  void end() const {
    if (!done()) fail("unexpected '" + t_[i_].text + "' after a complete expectation");
  }

  double number(const std::string& what) {
    const Token& t = next(what);
    const char* b = t.text.c_str();
    char* e = nullptr;
    const double v = std::strtod(b, &e);
    if (t.regex || e == b || *e != '\0' || !std::isfinite(v))
      fail_at(t, "expected " + what + " (a number), got '" + t.text + "'");
    return v;
  }
  double time(const std::string& what) {
    const size_t at = here();
    const double v = number(what);
    if (v < 0) throw ExpectationError(at, what + " must be >= 0 s");
    return v;
  }

  static bool is_op(const std::string& w) {
    return w == "<" || w == "<=" || w == ">" || w == ">=" || w == "==" || w == "!=" || w == "between";
  }
  bool at_op() const { return !done() && !t_[i_].regex && is_op(t_[i_].text); }

  Comparison comparison() {
    const Token& t = next("a comparison (<, <=, >, >=, ==, != or between)");
    Comparison c;
    if (t.text == "<") c.op = Comparison::Op::lt;
    else if (t.text == "<=") c.op = Comparison::Op::le;
    else if (t.text == ">") c.op = Comparison::Op::gt;
    else if (t.text == ">=") c.op = Comparison::Op::ge;
    else if (t.text == "==") c.op = Comparison::Op::eq;
    else if (t.text == "!=") c.op = Comparison::Op::ne;
    else if (t.text == "between") c.op = Comparison::Op::between;
    else fail_at(t, "expected a comparison (<, <=, >, >=, ==, != or between), got '" + t.text + "'");
    c.a = number("a value");
    if (c.op == Comparison::Op::between) {
      if (!accept("and")) fail("expected 'and' (between A and B)");
      const size_t at = here();
      c.b = number("the upper bound");
      if (c.b < c.a) throw ExpectationError(at, "between A and B needs A <= B");
    }
    return c;
  }

  Timing timing() {
    Timing tm;
    if (accept("before")) {
      tm.mode = Timing::Mode::before;
      tm.t_s = time("a time");
    } else if (accept("after")) {
      tm.mode = Timing::Mode::after;
      tm.t_s = time("a time");
    } else if (accept("never")) {
      tm.mode = Timing::Mode::never;
    } else if (accept("count")) {
      tm.mode = Timing::Mode::count;
      tm.count = comparison();
    } else {
      fail(done() ? "expected 'before T', 'after T', 'never' or 'count <comparison>', the expectation ends"
                  : "expected 'before T', 'after T', 'never' or 'count <comparison>', got '" + peek()->text + "'");
    }
    return tm;
  }

  EndpointName endpoint(const std::string& what) {
    const Token& t = next(what);
    EndpointName e;
    if (t.text == "central") {
      e.central = true;
      return e;
    }
    const std::string& w = t.text;
    bool ok = !t.regex && w.size() >= 2 && w.size() <= 4 && w[0] == 'm';
    for (size_t k = 1; ok && k < w.size(); ++k) ok = std::isdigit(static_cast<unsigned char>(w[k]));
    if (!ok) fail_at(t, "expected " + what + " (m0, m1, ... or central), got '" + w + "'");
    e.module = std::atoi(w.c_str() + 1);
    return e;
  }

  int address(const std::string& what) {
    const Token& t = next(what);
    const std::string& w = t.text;
    char* e = nullptr;
    const long v = (w.size() > 2 && w[0] == '0' && (w[1] == 'x' || w[1] == 'X')) ? std::strtol(w.c_str() + 2, &e, 16) : -1;
    if (t.regex || v < 0 || v > 0x7f || !e || *e != '\0')
      fail_at(t, "expected " + what + " (an I2C address 0x00..0x7f), got '" + w + "'");
    return static_cast<int>(v);
  }

 private:
  const std::string& s_;
  std::vector<Token> t_;
  size_t i_ = 0;
};

// A log pattern for RE2. Patterns are written in the ECMAScript syntax
// (docs/testing.md), which RE2 shares but for a few constructs: the ones that
// need backtracking, which RE2 does not do so as to match in linear time,
// are refused here, where they are written; \uXXXX and (?<name>...) are
// rewritten to RE2's \x{XXXX} and (?P<name>...). Anything else RE2 cannot
// read is refused by RE2 itself.
std::string re2_pattern(const Token& t) {
  const std::string& p = t.text;
  auto refuse = [&](size_t k, const std::string& what) {
    throw ExpectationError(t.src[k], "unsupported pattern /" + p + "/: " + what);
  };
  const std::string linear =
      ": patterns are matched by RE2, in time linear in the line, without backreferences or lookaround "
      "(docs/testing.md)";
  std::string out;
  bool in_class = false;
  for (size_t k = 0; k < p.size(); ++k) {
    const char c = p[k];
    if (c == '\\' && k + 1 < p.size()) {
      const char d = p[k + 1];
      if (!in_class && d >= '1' && d <= '9') refuse(k, std::string("'\\") + d + "' is a backreference" + linear);
      if (!in_class && d == 'k' && k + 2 < p.size() && p[k + 2] == '<')
        refuse(k, "'\\k<' is a backreference" + linear);
      if (d == 'u' && k + 6 <= p.size() &&
          std::isxdigit(static_cast<unsigned char>(p[k + 2])) && std::isxdigit(static_cast<unsigned char>(p[k + 3])) &&
          std::isxdigit(static_cast<unsigned char>(p[k + 4])) && std::isxdigit(static_cast<unsigned char>(p[k + 5]))) {
        out += "\\x{" + p.substr(k + 2, 4) + "}";
        k += 5;
        continue;
      }
      out += c;
      out += d;
      ++k;
      continue;
    }
    if (in_class) {
      if (c == ']') in_class = false;
      out += c;
      continue;
    }
    if (c == '[') {
      // ECMAScript's [] matches nothing and [^] any character; RE2 reads a
      // ']' first in a class as the character ']'
      const size_t first = k + 1 < p.size() && p[k + 1] == '^' ? k + 2 : k + 1;
      if (first < p.size() && p[first] == ']')
        refuse(k, "'" + p.substr(k, first - k + 1) + "' would be read otherwise by RE2, which takes a ']' first in " +
                      "a class as the character ']': write '.' for any character, '\\]' for the character ']'");
      in_class = true;
      out += c;
      continue;
    }
    if (c == '(' && k + 2 < p.size() && p[k + 1] == '?') {
      const char d = p[k + 2];
      if (d == '=' || d == '!') refuse(k, std::string("'(?") + d + "' is a lookahead" + linear);
      if (d == '<' && k + 3 < p.size() && (p[k + 3] == '=' || p[k + 3] == '!'))
        refuse(k, std::string("'(?<") + p[k + 3] + "' is a lookbehind" + linear);
      if (d == '<') {  // a named group
        out += "(?P<";
        k += 2;
        continue;
      }
    }
    out += c;
  }
  return out;
}

void parse_bus(Parser& p, Expectation* e) {
  const Token& ev = p.next("a bus event (i2c, i2c-drop, addr or sout)");
  e->event = ev.text;
  if (ev.text == "i2c" || ev.text == "i2c-drop") {
    for (;;) {
      if (p.accept("from")) {
        e->from = p.endpoint("a sender");
      } else if (p.accept("to")) {
        e->address = p.address("the address sent to");
      } else if (ev.text == "i2c" && p.accept("data")) {
        const Token& d = p.next("a hex prefix of the frame's bytes");
        bool hex = !d.regex && d.text.size() % 2 == 0;
        for (char c : d.text) hex = hex && std::isxdigit(static_cast<unsigned char>(c));
        if (!hex) p.fail_at(d, "expected the frame's first bytes in hex (e.g. 10 or 1001), got '" + d.text + "'");
        for (char c : d.text) e->data_prefix += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      } else {
        break;
      }
    }
  } else if (ev.text == "addr") {
    e->who = p.endpoint("the endpoint taking an address");
    if (p.peek() && p.peek()->text.rfind("0x", 0) == 0) e->address = p.address("the address taken");
  } else if (ev.text == "sout") {
    e->who = p.endpoint("the endpoint whose Sout changes");
    if (p.accept("1")) e->level = 1;
    else if (p.accept("0")) e->level = 0;
  } else {
    p.fail_at(ev, "unknown bus event '" + ev.text + "' (known: i2c, i2c-drop, addr, sout)");
  }
  e->timing = p.timing();
}

}  // namespace

bool Comparison::holds(double v) const {
  switch (op) {
    case Op::lt: return v < a;
    case Op::le: return v <= a;
    case Op::gt: return v > a;
    case Op::ge: return v >= a;
    case Op::eq: return v == a;
    case Op::ne: return v != a;
    case Op::between: return v >= a && v <= b;
  }
  return false;
}

std::string Comparison::text() const {
  std::ostringstream s;
  s.precision(12);
  switch (op) {
    case Op::lt: s << "< " << a; break;
    case Op::le: s << "<= " << a; break;
    case Op::gt: s << "> " << a; break;
    case Op::ge: s << ">= " << a; break;
    case Op::eq: s << "== " << a; break;
    case Op::ne: s << "!= " << a; break;
    case Op::between: s << "between " << a << " and " << b; break;
  }
  return s.str();
}

bool pattern_found(const Expectation& e, const std::string& line) {
  return e.regex && RE2::PartialMatch(line, *e.regex);
}

Expectation parse_expectation(const std::string& text) {
  Expectation e;
  e.text = text;
  Parser p(text);
  if (p.done()) throw ExpectationError(0, "empty expectation");
  const Token& first = p.next("an expectation");
  const std::string& w = first.text;
  if (first.regex) p.fail_at(first, "an expectation cannot start with a pattern");

  if (w == "no_faults") {
    e.kind = Expectation::Kind::no_faults;
  } else if (w == "log") {
    e.kind = Expectation::Kind::log;
    e.who = p.endpoint("whose log (m0, m1, ... or central)");
    const Token& re = p.next("a pattern /.../");
    if (!re.regex) p.fail_at(re, "expected a pattern between slashes, e.g. /contact/, got '" + re.text + "'");
    e.pattern = re.text;
    RE2::Options opt;
    opt.set_log_errors(false);  // the error is ours to report, at its place
    auto rx = std::make_shared<const RE2>(re2_pattern(re), opt);
    if (!rx->ok()) p.fail_at(re, "bad pattern /" + re.text + "/: " + rx->error());
    e.regex = std::move(rx);
    e.timing = p.timing();
  } else if (w == "bus") {
    e.kind = Expectation::Kind::bus;
    parse_bus(p, &e);
  } else if (w == "touch") {
    e.kind = Expectation::Kind::touch;
    e.who = p.endpoint("the touch module");
    if (e.who.central) p.fail_at(first, "touch needs a module (m0, m1, ...), not the central control");
    e.timing = p.timing();
  } else if (w.rfind("trace.", 0) == 0) {
    e.path = w.substr(6);
    if (e.path.empty()) p.fail_at(first, "expected a trace column after 'trace.', e.g. trace.m0.s0.current_a");
    if (p.at_op()) {
      e.kind = Expectation::Kind::trace_when;
      e.cmp = p.comparison();
      e.timing = p.timing();
      if (e.timing.mode == Timing::Mode::count)
        throw ExpectationError(text.find("count"), "a trace condition takes before, after or never, not count");
    } else {
      e.kind = Expectation::Kind::trace_stat;
      if (p.accept("final")) e.stat = Expectation::Stat::final_value;
      else if (p.accept("max")) e.stat = Expectation::Stat::max;
      else if (p.accept("min")) e.stat = Expectation::Stat::min;
      else if (p.accept("mean")) e.stat = Expectation::Stat::mean;
      else if (p.accept("at")) {
        e.stat = Expectation::Stat::at;
        e.at_s = p.time("a time");
      } else {
        p.fail(p.done() ? "expected final, max, min, mean, at T or a comparison after the column"
                        : "expected final, max, min, mean, at T or a comparison after the column, got '" +
                              p.peek()->text + "'");
      }
      e.cmp = p.comparison();
    }
  } else if (w.rfind("motion.", 0) == 0) {
    e.kind = Expectation::Kind::motion;
    e.path = w.substr(7);
    if (e.path.empty()) p.fail_at(first, "expected a motion metric after 'motion.', e.g. motion.dx_m");
    e.cmp = p.comparison();
  } else {
    // a number of summary.json: a dotted path of keys and list indices
    bool ok = std::isalpha(static_cast<unsigned char>(w[0])) || w[0] == '_';
    for (char c : w) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.');
    if (!ok || w.back() == '.' || w.find("..") != std::string::npos)
      p.fail_at(first, "unknown expectation '" + w +
                           "' (known: no_faults, a summary.json path such as chain.distance_m, motion.<metric>, "
                           "trace.<column>, log, bus, touch)");
    e.kind = Expectation::Kind::summary;
    e.path = w;
    e.cmp = p.comparison();
  }
  p.end();
  return e;
}

}  // namespace chainsim
