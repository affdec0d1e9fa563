// The expectation grammar (docs/testing.md): each kind parses to what it
// measures, and a mistake is reported at the character at fault.
#include <gtest/gtest.h>

#include <string>

#include "testing/expectation.h"

using namespace chainsim;

namespace {

// the offset an ExpectationError points at, or -1 when it parses
long error_at(const std::string& text, std::string* what = nullptr) {
  try {
    parse_expectation(text);
  } catch (const ExpectationError& e) {
    if (what) *what = e.what();
    return static_cast<long>(e.offset);
  }
  return -1;
}

}  // namespace

TEST(Expectation, SummaryPathWithComparison) {
  const Expectation e = parse_expectation("chain.distance_m >= 0.2");
  EXPECT_EQ(e.kind, Expectation::Kind::summary);
  EXPECT_EQ(e.path, "chain.distance_m");
  EXPECT_EQ(e.cmp.op, Comparison::Op::ge);
  EXPECT_DOUBLE_EQ(e.cmp.a, 0.2);
  const Expectation b = parse_expectation("modules.2.energy_j between 0.5 and 3");
  EXPECT_EQ(b.cmp.op, Comparison::Op::between);
  EXPECT_DOUBLE_EQ(b.cmp.a, 0.5);
  EXPECT_DOUBLE_EQ(b.cmp.b, 3);
}

TEST(Expectation, ComparisonsHoldAsWritten) {
  auto cmp = [](const std::string& s) { return parse_expectation("x " + s).cmp; };
  EXPECT_TRUE(cmp("< 1").holds(0.5));
  EXPECT_FALSE(cmp("< 1").holds(1));
  EXPECT_TRUE(cmp("<= 1").holds(1));
  EXPECT_TRUE(cmp("> -1").holds(0));
  EXPECT_FALSE(cmp(">= 2").holds(1.999));
  EXPECT_TRUE(cmp("== 3").holds(3));
  EXPECT_TRUE(cmp("!= 3").holds(2));
  EXPECT_TRUE(cmp("between -1 and 1").holds(-1));
  EXPECT_TRUE(cmp("between -1 and 1").holds(1));
  EXPECT_FALSE(cmp("between -1 and 1").holds(1.0001));
  EXPECT_EQ(cmp("between -1 and 1").text(), "between -1 and 1");
  EXPECT_EQ(cmp(">= 0.25").text(), ">= 0.25");
}

TEST(Expectation, TraceStatisticsAndConditions) {
  const Expectation m = parse_expectation("trace.m0.s0.current_a max < 0.35");
  EXPECT_EQ(m.kind, Expectation::Kind::trace_stat);
  EXPECT_EQ(m.path, "m0.s0.current_a");
  EXPECT_EQ(m.stat, Expectation::Stat::max);
  const Expectation a = parse_expectation("trace.m1.body.z at 2.5 > 0.01");
  EXPECT_EQ(a.stat, Expectation::Stat::at);
  EXPECT_DOUBLE_EQ(a.at_s, 2.5);
  for (const char* s : {"final", "min", "mean"})
    EXPECT_EQ(parse_expectation(std::string("trace.t_s ") + s + " > 0").kind, Expectation::Kind::trace_stat);
  const Expectation w = parse_expectation("trace.m0.cover.y > 0.13 before 9");
  EXPECT_EQ(w.kind, Expectation::Kind::trace_when);
  EXPECT_EQ(w.timing.mode, Timing::Mode::before);
  EXPECT_DOUBLE_EQ(w.timing.t_s, 9);
  EXPECT_EQ(parse_expectation("trace.m0.cover.y > 0.13 never").timing.mode, Timing::Mode::never);
}

TEST(Expectation, LogPatternsKeepBlanksAndEscapedSlashes) {
  const Expectation e = parse_expectation("log central /chain: RRR \\(3 modules\\)/ before 0.3");
  EXPECT_EQ(e.kind, Expectation::Kind::log);
  EXPECT_TRUE(e.who.central);
  EXPECT_EQ(e.pattern, "chain: RRR \\(3 modules\\)");
  EXPECT_TRUE(pattern_found(e, "chain: RRR (3 modules)"));
  EXPECT_FALSE(pattern_found(e, "chain: RRR 3 modules"));
  const Expectation s = parse_expectation("log m12 /a\\/b/ count >= 2");
  EXPECT_EQ(s.who.module, 12);
  EXPECT_EQ(s.pattern, "a/b");
  EXPECT_EQ(s.timing.mode, Timing::Mode::count);
  EXPECT_EQ(s.timing.count.op, Comparison::Op::ge);
  EXPECT_EQ(parse_expectation("log m0 /x/ after 1.5").timing.mode, Timing::Mode::after);
}

TEST(Expectation, BusEventsWithFilters) {
  const Expectation i = parse_expectation("bus i2c to 0x20 before 0.5");
  EXPECT_EQ(i.kind, Expectation::Kind::bus);
  EXPECT_EQ(i.event, "i2c");
  ASSERT_TRUE(i.address);
  EXPECT_EQ(*i.address, 0x20);
  EXPECT_FALSE(i.from);
  const Expectation f = parse_expectation("bus i2c from central to 0x21 data 10 count == 1");
  ASSERT_TRUE(f.from);
  EXPECT_TRUE(f.from->central);
  EXPECT_EQ(f.data_prefix, "10");
  const Expectation a = parse_expectation("bus addr m3 0x23 before 0.3");
  EXPECT_EQ(a.who.module, 3);
  EXPECT_EQ(*a.address, 0x23);
  const Expectation s = parse_expectation("bus sout m0 1 before 0.1");
  EXPECT_EQ(*s.level, 1);
  EXPECT_EQ(parse_expectation("bus i2c-drop never").event, "i2c-drop");
  const Expectation t = parse_expectation("touch m0 before 8");
  EXPECT_EQ(t.kind, Expectation::Kind::touch);
  EXPECT_DOUBLE_EQ(t.timing.t_s, 8);
}

TEST(Expectation, NoFaultsAndMotion) {
  EXPECT_EQ(parse_expectation("no_faults").kind, Expectation::Kind::no_faults);
  const Expectation m = parse_expectation("motion.m3.body.twist_deg > 720");
  EXPECT_EQ(m.kind, Expectation::Kind::motion);
  EXPECT_EQ(m.path, "m3.body.twist_deg");
}

TEST(Expectation, ErrorsPointAtTheCharacterAtFault) {
  std::string what;
  EXPECT_EQ(error_at("chain.distance_m >= x", &what), 20);
  EXPECT_NE(what.find("a number"), std::string::npos) << what;
  EXPECT_EQ(error_at("chain.distance_m => 1", &what), 17);
  EXPECT_NE(what.find("comparison"), std::string::npos) << what;
  EXPECT_EQ(error_at("trace.m0.x maximum < 1", &what), 11);
  EXPECT_NE(what.find("final, max, min, mean"), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /contact before 8", &what), 7);
  EXPECT_NE(what.find("closing '/'"), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /(/ before 8", &what), 7);
  EXPECT_NE(what.find("bad pattern"), std::string::npos) << what;
  EXPECT_EQ(error_at("log x0 /a/ before 8", &what), 4);
  EXPECT_EQ(error_at("bus can to 0x20 before 1", &what), 4);
  EXPECT_NE(what.find("known: i2c, i2c-drop, addr, sout"), std::string::npos) << what;
  EXPECT_EQ(error_at("bus i2c to 0x200 before 1", &what), 11);
  EXPECT_EQ(error_at("touch m0 before -1", &what), 16);
  EXPECT_EQ(error_at("touch m0 soon", &what), 9);
  EXPECT_EQ(error_at("no_faults please", &what), 10);
  EXPECT_NE(what.find("unexpected 'please'"), std::string::npos) << what;
  EXPECT_EQ(error_at("x between 2 and 1"), 16);
  EXPECT_EQ(error_at("chain.distance_m >="), 19);  // the end
  EXPECT_EQ(error_at("2fast > 1", &what), 0);
  EXPECT_NE(what.find("unknown expectation"), std::string::npos) << what;
  EXPECT_EQ(error_at(""), 0);
}

// Patterns are matched by RE2: nested quantifiers over a long line take one
// pass, not the 2^n steps of a backtracking engine (no time is measured: a
// backtracking engine would not finish, and the test's TIMEOUT would end it)
TEST(Expectation, NestedQuantifiersOverALongLineAreMatchedInLinearTime) {
  const std::string as(100000, 'a');
  const Expectation e = parse_expectation("log m0 /^(a+)+$/ never");
  EXPECT_FALSE(pattern_found(e, as + "b"));
  EXPECT_TRUE(pattern_found(e, as));
  const Expectation f = parse_expectation("log m0 /(a|aa)+c/ never");
  EXPECT_FALSE(pattern_found(f, as + "b"));
  EXPECT_TRUE(pattern_found(f, as + "c"));
  const Expectation g = parse_expectation("log m0 /(.*a){20}$/ never");
  EXPECT_FALSE(pattern_found(g, as + "b"));
}

// the ECMAScript syntax the test files use means the same under RE2
TEST(Expectation, PatternSyntaxOfTheTestFiles) {
  struct Case {
    const char* pattern;
    const char* line;
    bool found;
  } const cases[] = {
      {"chain: RRRRRRRR \\(8 modules\\)", "chain: RRRRRRRR (8 modules)", true},
      {"sensors 0x20:", "t=1 sensors 0x20: 12 3", true},
      {"^start", "a start", false},
      {"modules\\)$", "chain: R (1 modules)", true},
      {"\\d+ modules", "chain: R (12 modules)", true},
      {"\\bgait\\b", "gaits", false},
      {"[^ ]+: contact", "touch 0x20: contact", true},
      {"(?:ab)+c", "xababc", true},
      {"a.c", "abc", true},
      {"a.+?c", "abbbc", true},
      {"x{2,3}", "axxb", true},
      {"A|B", "C", false},
      {"\\u0041\\u00e9", "A\xc3\xa9", true},       // \uXXXX, read as UTF-8
      {"(?<n>ab)c", "abc", true},                  // a named group
      {"a\\/b", "a/b", true},                      // '\/' for a slash
      {"[\\]x]+", "]x]", true},
  };
  for (const Case& c : cases) {
    const Expectation e = parse_expectation(std::string("log m0 /") + c.pattern + "/ never");
    EXPECT_EQ(pattern_found(e, c.line), c.found) << c.pattern << " on " << c.line;
  }
}

// what RE2 has not (it would need backtracking) is refused where it is
// written, when the file is loaded, not when the log is matched
TEST(Expectation, BackreferencesAndLookaroundAreRefusedWhereWritten) {
  std::string what;
  EXPECT_EQ(error_at("log m0 /(a)\\1/ never", &what), 11);
  EXPECT_NE(what.find("unsupported pattern /(a)\\1/: '\\1' is a backreference: patterns are matched by RE2, in "
                      "time linear in the line, without backreferences or lookaround"),
            std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /(?<x>a)\\k<x>/ never", &what), 15);
  EXPECT_NE(what.find("'\\k<' is a backreference"), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /chain(?= RRR)/ never", &what), 13);
  EXPECT_NE(what.find("'(?=' is a lookahead"), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /a(?!b)/ never", &what), 9);
  EXPECT_NE(what.find("'(?!' is a lookahead"), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /(?<=a)b/ never", &what), 8);
  EXPECT_NE(what.find("'(?<=' is a lookbehind"), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /(?<!a)b/ never", &what), 8);
  EXPECT_NE(what.find("'(?<!' is a lookbehind"), std::string::npos) << what;
  // after an escaped slash: the offset is in the expectation as written
  EXPECT_EQ(error_at("log m0 /a\\/b(?=c)/ never", &what), 12);
  // [] and [^] mean another thing to RE2
  EXPECT_EQ(error_at("log m0 /x[^]/ never", &what), 9);
  EXPECT_NE(what.find("'[^]' would be read otherwise by RE2"), std::string::npos) << what;
  // what RE2 cannot read is a bad pattern, at the pattern
  EXPECT_EQ(error_at("log m0 /a{2,1}/ never", &what), 7);
  EXPECT_NE(what.find("bad pattern /a{2,1}/: "), std::string::npos) << what;
  EXPECT_EQ(error_at("log m0 /a\\cJ/ never", &what), 7);
  EXPECT_NE(what.find("bad pattern"), std::string::npos) << what;
  // inside a class, \1 and (?= are no backreference or lookahead
  EXPECT_EQ(error_at("log m0 /[(?=]/ never"), -1);
}
