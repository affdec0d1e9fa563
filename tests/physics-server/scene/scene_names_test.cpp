// Names from a scene that reach paths, the wire and the terminal: a scene
// name names the run directory (runs/<name>-<date>), so it cannot climb out
// of runs/; text must be printable UTF-8; messages show the culprit escaped.
#include <gtest/gtest.h>

#include <string>

#include "readers/safe_text.h"
#include "scene/scene.h"
#include "scene_error_of.h"

using chainsim::load_scene_text;
using chainsim::testing::scene_error_of;

TEST(SceneNames, NameThatLeavesTheRunsDirectoryIsRefused) {
  EXPECT_EQ(scene_error_of("chain: R\nname: ../../../X\n"),
            "s.yaml:2:7: 'scene.name' = '../../../X' must be 1 to 63 letters, digits, '_', '-' or '.', "
            "not starting with '.' or '-'");
  EXPECT_NE(scene_error_of("chain: R\nname: a/b\n").find("s.yaml:2:7: 'scene.name' = 'a/b' must be"), std::string::npos);
  EXPECT_NE(scene_error_of("chain: R\nname: ..\n").find("s.yaml:2:7: 'scene.name'"), std::string::npos);
  EXPECT_NE(scene_error_of("chain: R\nname: --out\n").find("s.yaml:2:7: 'scene.name'"), std::string::npos);
  EXPECT_NE(scene_error_of("chain: R\nname: \"\"\n").find("s.yaml:2:7: 'scene.name'"), std::string::npos);
  EXPECT_EQ(load_scene_text("chain: R\nname: snake_v1.2-b\n", "s.yaml").name, "snake_v1.2-b");
}

// used to be exit 3 with "json.exception.type_error.316" and no file named
TEST(SceneNames, InvalidUtf8IsRefusedAndShownEscaped) {
  const std::string e = scene_error_of("chain: R\nname: a\xFF" "b\n");  // a raw byte, not a YAML escape
  EXPECT_NE(e.find("s.yaml:2:7: 'scene.name' must be printable UTF-8 text, not 'a\\xFFb'"), std::string::npos) << e;
  const std::string f = scene_error_of("chain: R\ncentral: {program: \"fw\\x1b[31m\"}\n");
  EXPECT_NE(f.find("'central.program' must be printable UTF-8 text, not 'fw\\x1B[31m'"), std::string::npos) << f;
  EXPECT_EQ(f.find('\x1b'), std::string::npos);
}

// used to be accepted, and the module then failed to connect (a 10 s stall)
TEST(SceneNames, ParameterNameWithAControlCharacterIsRefused) {
  const std::string e = scene_error_of("chain:\n  - {type: rotation, params: {\"a\\nb\": 1}}\n");
  EXPECT_NE(e.find("s.yaml:2:31: parameter name 'a\\x0Ab' must be 1 to 15 letters, digits or '_'"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
  EXPECT_NE(scene_error_of("chain: R\ncentral: {params: {\"a b\": 1}}\n").find("parameter name 'a b'"), std::string::npos);
}

// an unknown key with ESC in it is echoed escaped, never raw
TEST(SceneNames, UnknownKeyIsShownEscaped) {
  const std::string e = scene_error_of("chain: R\n\"x\\e]0;pwned\\a\": 1\n");
  EXPECT_NE(e.find("unknown key 'x\\x1B]0;pwned\\x07'"), std::string::npos) << e;
  EXPECT_EQ(e.find('\x1b'), std::string::npos);
}

TEST(SafeText, PrintableUtf8) {
  using chainsim::is_printable_text;
  EXPECT_TRUE(is_printable_text("tubería ø 管"));
  EXPECT_FALSE(is_printable_text("a\tb"));
  EXPECT_FALSE(is_printable_text("\xC0\xAF"));          // overlong '/'
  EXPECT_FALSE(is_printable_text("\xED\xA0\x80"));      // a surrogate
  EXPECT_FALSE(is_printable_text("\xC2\x9B" "31m"));    // C1 CSI
  EXPECT_FALSE(is_printable_text("\xE2\x82"));          // cut short
  EXPECT_EQ(chainsim::shown_text("a\x1b\xff"), "a\\x1B\\xFF");
}
