// The strict YAML reader: file:line:column on every error, unknown keys that
// name the known ones, numbers checked for type, finiteness and range, and
// the loader's own error type.
#include "readers/strict_yaml.h"

#include <gtest/gtest.h>

#include <string>

namespace chainsim {
namespace {

struct LoaderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

const StrictYaml kY("f.yaml");

template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const YamlError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(StrictYaml, SyntaxErrorGivesTheParserPosition) {
  const std::string e = error_of([] { kY.parse("a: [1, 2\n"); });
  EXPECT_EQ(e.rfind("f.yaml:", 0), 0u) << e;
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
}

TEST(StrictYaml, UnknownKeyNamesItsPlaceAndTheKnownKeys) {
  const YAML::Node n = kY.parse("servo:\n  Kp: 1\n  Kq: 2\n");
  EXPECT_EQ(error_of([&] { kY.keys(n["servo"], "servo", {"Kp", "Km"}); }),
            "f.yaml:3:3: unknown key 'Kq' in 'servo' (known: Km, Kp)");
  EXPECT_EQ(error_of([&] { kY.keys(n["servo"]["Kp"], "servo.Kp", {"x"}); }), "f.yaml:2:7: 'servo.Kp' must be a mapping");
}

TEST(StrictYaml, NumbersAreCheckedForTypeFinitenessAndRange) {
  const YAML::Node n = kY.parse("a: abc\nb: .nan\nc: -0.03\nd: 2\ne: [1]\nf: 0.5\n");
  EXPECT_EQ(error_of([&] { kY.number(n, "a", 0, 0, 1, "m"); }), "f.yaml:1:4: 'm.a' must be a number, not 'abc'");
  EXPECT_EQ(error_of([&] { kY.number(n, "b", 0, 0, 1, "m"); }),
            "f.yaml:2:4: 'm.b' must be a finite number, not '.nan'");
  EXPECT_EQ(error_of([&] { kY.positive(n, "c", 1, 10, "m"); }), "f.yaml:3:4: 'm.c' = -0.03 must be > 0");
  EXPECT_EQ(error_of([&] { kY.number(n, "d", 0, 0, 1, "m"); }), "f.yaml:4:4: 'm.d' = 2 is out of range [0, 1]");
  EXPECT_EQ(error_of([&] { kY.number(n, "f", 0, 0.5, 1, "m", true); }),
            "f.yaml:6:4: 'm.f' = 0.5 is out of range (0.5, 1]");
  EXPECT_EQ(error_of([&] { kY.number_at(n["e"], "e", 0, 1); }), "f.yaml:5:4: 'e' must be a number");
  EXPECT_EQ(kY.number(n, "f", 0, 0, 1, "m"), 0.5);
  EXPECT_EQ(kY.number(n, "absent", 7, 0, 1, "m"), 7);  // the default is not range-checked
}

TEST(StrictYaml, IntegersTextsFlagsVectorsChoices) {
  const YAML::Node n = kY.parse("i: 12.5\nj: 40\nt: ''\nb: maybe\nv: [1, 2]\nc: cave\nok: [1, 2, 3]\n");
  EXPECT_EQ(error_of([&] { kY.integer(n, "i", 0, 0, 100, "m"); }), "f.yaml:1:4: 'm.i' must be an integer, not '12.5'");
  EXPECT_EQ(error_of([&] { kY.integer(n, "j", 0, 0, 10, "m"); }), "f.yaml:2:4: 'm.j' = 40 is out of range [0, 10]");
  EXPECT_EQ(kY.integer(n, "j", 0, 0, 100, "m"), 40);
  EXPECT_EQ(error_of([&] { kY.text(n, "t", "", "m"); }), "f.yaml:3:4: 'm.t' must be a non-empty string");
  EXPECT_EQ(kY.string(n, "t", "x", "m"), "");
  EXPECT_EQ(error_of([&] { kY.flag(n, "b", false, "m"); }), "f.yaml:4:4: 'm.b' must be true or false");
  EXPECT_EQ(error_of([&] { kY.vec3(n, "v", {}, "m"); }), "f.yaml:5:4: 'm.v' must be a list of 3 numbers [x, y, z]");
  EXPECT_EQ(kY.vec3(n, "ok", {}, "m"), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(error_of([&] { kY.choice(n, "c", "plane", {"plane", "pipe"}, "m"); }),
            "f.yaml:6:4: 'm.c' 'cave' is not known (known: plane, pipe)");
  EXPECT_EQ(kY.choice(n, "absent", "pipe", {"plane", "pipe"}, "m"), "pipe");
}

TEST(StrictYaml, VectorElementsAreFiniteAndWithinTheirLimit) {
  const YAML::Node n = kY.parse("p: [0, .inf, 1]\nq: [1e300, 0, 0]\nr: [1, 2, x]\nd: [0, 400, 0]\n");
  EXPECT_EQ(error_of([&] { kY.vec3(n, "p", {}, "m"); }), "f.yaml:1:8: 'm.p[1]' must be a finite number, not '.inf'");
  EXPECT_EQ(error_of([&] { kY.vec3(n, "q", {}, "m"); }),
            "f.yaml:2:5: 'm.q[0]' = 1e300 is out of range [-10000, 10000]");
  EXPECT_EQ(error_of([&] { kY.vec3(n, "r", {}, "m"); }), "f.yaml:3:11: 'm.r[2]' must be a number, not 'x'");
  EXPECT_EQ(error_of([&] { kY.vec3(n, "d", {}, "m", 360); }), "f.yaml:4:8: 'm.d[1]' = 400 is out of range [-360, 360]");
}

// yaml-cpp keeps both entries of a key given twice and returns the first:
// the reader refuses it at the second, naming the first
TEST(StrictYaml, DuplicateKeyIsAnErrorAtAnyDepth) {
  EXPECT_EQ(error_of([] { kY.parse("a: 1\nb: 2\na: 3\n"); }), "f.yaml:3:1: duplicate key 'a' (first at line 1, column 1)");
  EXPECT_EQ(error_of([] { kY.parse("l:\n  - {x: 1, y: 2, x: 1}\n"); }),
            "f.yaml:2:18: duplicate key 'x' (first at line 2, column 6)");
  EXPECT_EQ(error_of([] { kY.parse("a: {x: 1}\nb: {x: 1}\n"); }), "(no error)");  // same key, two mappings
}

// a loader reads each key as text: a key that is not used to abort the program
TEST(StrictYaml, KeyThatIsNotTextIsAnError) {
  EXPECT_EQ(error_of([] { kY.parse("a: 1\n? [x, y]\n: 2\n"); }), "f.yaml:2:3: a key must be text, not a list");
  EXPECT_EQ(error_of([] { kY.parse("a: {b: {{c: 1}: 2}}\n"); }), "f.yaml:1:9: a key must be text, not a mapping");
  EXPECT_EQ(error_of([] { kY.parse("a:\n  ~: 1\n"); }), "f.yaml:2:3: a key must be text, not null");
  EXPECT_EQ(error_of([] { kY.parse("a:\n  '~': 1\n  \"\": 2\n"); }), "(no error)");  // quoted: text
}

TEST(StrictYaml, SecondDocumentIsAnError) {
  EXPECT_EQ(error_of([] { kY.parse("a: 1\n---\nb: 2\n"); }).rfind("f.yaml:3:1: a second YAML document", 0), 0u)
      << error_of([] { kY.parse("a: 1\n---\nb: 2\n"); });
  // a broken second document is a syntax error, not ignored
  EXPECT_NE(error_of([] { kY.parse("a: 1\n---\nb: [\n"); }).find("YAML syntax error"), std::string::npos);
  EXPECT_EQ(error_of([] { kY.parse("---\na: 1\n"); }), "(no error)");  // one document with its marker
  EXPECT_EQ(error_of([] { kY.parse(""); }), "(no error)");
}

TEST(StrictYaml, NestingAndAliasExpansionAreBounded) {
  EXPECT_NE(error_of([] { kY.parse(std::string(100, '[') + std::string(100, ']')); }).find("nested deeper than 64"),
            std::string::npos);
  // each level doubles the values through aliases: 2^25 values, refused early
  std::string bomb = "a0: &a0 [x, x]\n";
  for (int i = 1; i <= 25; ++i)
    bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [*a" + std::to_string(i - 1) + ", *a" +
            std::to_string(i - 1) + "]\n";
  EXPECT_NE(error_of([&] { kY.parse(bomb); }).find("more than 1000000 values"), std::string::npos);
}

TEST(StrictYaml, ErrorsAreTheLoadersOwnType) {
  const StrictYaml y("g.yaml", [](const std::string& m) { throw LoaderError(m); });
  const YAML::Node n = y.parse("a: x\n");
  try {
    y.number(n, "a", 0, 0, 1, "m");
    FAIL() << "no error";
  } catch (const LoaderError& e) {
    EXPECT_STREQ(e.what(), "g.yaml:1:4: 'm.a' must be a number, not 'x'");
  }
  EXPECT_THROW(y.parse("a: [\n"), LoaderError);
  EXPECT_THROW(StrictYaml("/no/such/file.yaml", [](const std::string& m) { throw LoaderError(m); })
                   .read_file("the test file"),
               LoaderError);
}

}  // namespace
}  // namespace chainsim
