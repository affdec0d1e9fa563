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
