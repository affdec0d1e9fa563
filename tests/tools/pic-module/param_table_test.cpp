// A program's parameters in flash and in the data EEPROM
// (tools/pic-module/param_table.h).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "hal_pic_board.h"
#include "pic-module/param_table.h"

using namespace chainsim::pic;

namespace {

// a flash image holding hal_param_table at 0x100 as SDCC lays it out
struct Flash {
  std::map<uint32_t, uint8_t> bytes;
  uint32_t strings = 0x200;
  void put32(uint32_t a, int32_t v) {
    for (int k = 0; k < 4; ++k) bytes[a + k] = static_cast<uint8_t>(static_cast<uint32_t>(v) >> (8 * k));
  }
  void entry(uint32_t at, const std::string& name, int32_t min, int32_t max, int32_t def) {
    bytes[at] = static_cast<uint8_t>(strings & 0xFF);
    bytes[at + 1] = static_cast<uint8_t>(strings >> 8);
    bytes[at + 2] = 0;  // upper byte 0: program memory
    put32(at + 3, min);
    put32(at + 7, max);
    put32(at + 11, def);
    for (size_t i = 0; i <= name.size(); ++i) bytes[strings + static_cast<uint32_t>(i)] = i < name.size() ? name[i] : 0;
    strings += static_cast<uint32_t>(name.size()) + 1;
  }
  uint8_t operator()(uint32_t a) const {
    const auto it = bytes.find(a);
    return it == bytes.end() ? 0 : it->second;
  }
};

}  // namespace

TEST(ParamTable, ReadsTheTableSdccPutInFlash) {
  Flash f;
  f.entry(0x100, "control_ms", 1, 1000, 10);
  f.entry(0x10F, "amp_cdeg", -9000, 9000, -250);
  const auto t = read_param_table(0x100, [&](uint32_t a) { return f(a); });
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].name, "control_ms");
  EXPECT_EQ(t[0].min, 1);
  EXPECT_EQ(t[0].max, 1000);
  EXPECT_EQ(t[0].def, 10);
  EXPECT_EQ(t[1].name, "amp_cdeg");
  EXPECT_EQ(t[1].min, -9000);
  EXPECT_EQ(t[1].def, -250);
}

TEST(ParamTable, ANameOutsideFlashIsNoTable) {
  Flash f;
  f.bytes[0x102] = 0x80;  // a pointer to data memory
  f.bytes[0x100] = 1;
  EXPECT_THROW(read_param_table(0x100, [&](uint32_t a) { return f(a); }), std::runtime_error);
}

TEST(ParamTable, TheEepromGivesValuesByTheirIndexInTheTable) {
  const std::vector<FlashParam> t{{"control_ms", 1, 1000, 10}, {"amp_cdeg", -9000, 9000, 0}};
  const auto ee = params_eeprom(t, {{"amp_cdeg", -2000}});
  ASSERT_EQ(ee.size(), 2u + 5u);
  EXPECT_EQ(ee[0], HP_BOARD_PARAMS_MAGIC);
  EXPECT_EQ(ee[1], 1);
  EXPECT_EQ(ee[2], 1);  // amp_cdeg is the second entry
  const int32_t v = static_cast<int32_t>(ee[3] | ee[4] << 8 | ee[5] << 16 | static_cast<uint32_t>(ee[6]) << 24);
  EXPECT_EQ(v, -2000);
}

TEST(ParamTable, AParameterTheHexDoesNotDeclareIsNamed) {
  const std::vector<FlashParam> t{{"control_ms", 1, 1000, 10}};
  try {
    params_eeprom(t, {{"amp", 1}});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("parameter 'amp' is not declared by the program's .hex (it declares: "
                                         "control_ms)"),
              std::string::npos)
        << e.what();
  }
}
