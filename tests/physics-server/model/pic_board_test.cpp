// A module type against the PIC board's pins (model/pic_board.h).
#include <gtest/gtest.h>

#include <string>

#include "model/module_file.h"
#include "model/pic_board.h"

using namespace chainsim;

namespace {

// a passive body with the given sensors and servos
ModuleDef with(const std::string& sensors, int servos = 0) {
  std::string text =
      "type: probe\n"
      "bodies:\n"
      "  - {name: a, shape: box, size_m: [0.02, 0.02, 0.02], mass_kg: 0.01}\n";
  for (int i = 0; i < servos; ++i)
    text += "  - {name: b" + std::to_string(i) + ", shape: box, size_m: [0.02, 0.02, 0.02], mass_kg: 0.001, "
            "position_m: [" + std::to_string(-0.03 * (i + 1)) + ", 0, 0]}\n";
  if (servos > 0) {
    text += "joints:\n";
    for (int i = 0; i < servos; ++i)
      text += "  - {name: j" + std::to_string(i) + ", type: hinge, parent: " + (i ? "b" + std::to_string(i - 1) : "a") +
              ", child: b" + std::to_string(i) + ", anchor_m: [" + std::to_string(-0.015 - 0.03 * i) +
              ", 0, 0], axis: [0, 1, 0]}\n";
    text += "actuators:\n";
    for (int i = 0; i < servos; ++i)
      text += "  - {name: s" + std::to_string(i) + ", type: servo, joint: j" + std::to_string(i) + "}\n";
  }
  text += "sensors:\n" + sensors;
  text += "docking:\n  front: {body: a, position_m: [0.01, 0, 0]}\n  back: {body: a, position_m: [-0.01, 0, 0]}\n";
  return load_module_text(text, "probe.yaml");
}

}  // namespace

TEST(PicBoard, EveryShippedTypeFitsTheBoard) {
  for (const std::string& type : builtin_module_names())
    EXPECT_TRUE(pic_board_misfits(builtin_module_def(type)).empty())
        << type << ": " << pic_board_misfits(builtin_module_def(type)).front();
}

TEST(PicBoard, AnAccelerometerOnAdcFiveIsRefusedWithItsName) {
  const auto m = pic_board_misfits(with(
      "  - {name: tilt, type: accelerometer, body: a, channel: 3}\n"));
  ASSERT_EQ(m.size(), 1u);
  EXPECT_NE(m[0].find("sensor 'tilt' reads ADC channels 3..5"), std::string::npos) << m[0];
  EXPECT_NE(m[0].find("ADC channels 0..4 only"), std::string::npos) << m[0];
  EXPECT_TRUE(pic_board_misfits(with("  - {name: tilt, type: accelerometer, body: a, channel: 2}\n")).empty());
}

TEST(PicBoard, ServosTakeTheFirstAnalogInputs) {
  // two servos: their potentiometers on AN0 and AN1 leave ADC channels 0..2
  EXPECT_TRUE(pic_board_misfits(with("  - {name: tilt, type: accelerometer, body: a, channel: 0}\n", 2)).empty());
  const auto m = pic_board_misfits(with("  - {name: tilt, type: accelerometer, body: a, channel: 1}\n", 2));
  ASSERT_EQ(m.size(), 1u);
  EXPECT_NE(m[0].find("a module with 2 servos has ADC channels 0..2 only"), std::string::npos) << m[0];
}

TEST(PicBoard, CountersAndDigitalInputs) {
  // with a servo on RB2, INT2 is no counter (the traveller, without servos,
  // counts its third wheel there: EveryShippedTypeFitsTheBoard)
  const auto c = pic_board_misfits(with("  - {name: w, type: wheel_encoder, joint: j0, channel: 2}\n", 1));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NE(c[0].find("sensor 'w' counts on counter 2, but on the board a module with 1 servo has counters 0..1"),
            std::string::npos) << c[0];
  EXPECT_TRUE(pic_board_misfits(with("  - {name: w, type: wheel_encoder, joint: j0, channel: 1}\n", 1)).empty());
  const auto m = pic_board_misfits(with("  - {name: t, type: touch, body: a, channel: 4}\n"));
  ASSERT_EQ(m.size(), 1u);
  EXPECT_NE(m[0].find("digital input 4"), std::string::npos) << m[0];
  EXPECT_TRUE(pic_board_misfits(with("  - {name: t, type: touch, body: a, channel: 3}\n")).empty());
}
