// Parameters in flash and EEPROM. See param_table.h.
#include "pic-module/param_table.h"

#include "hal_pic_board.h"

namespace chainsim::pic {

namespace {

constexpr uint32_t kEntryBytes = 15;
constexpr int kMaxEntries = 64;
constexpr uint32_t kFlashBytes = 32768;
constexpr size_t kNameMax = 15;  // HAL_PARAM_NAME_MAX

}  // namespace

std::vector<FlashParam> read_param_table(uint32_t table, const std::function<uint8_t(uint32_t)>& byte) {
  auto i32 = [&](uint32_t a) {
    return static_cast<int32_t>(static_cast<uint32_t>(byte(a)) | static_cast<uint32_t>(byte(a + 1)) << 8 |
                                static_cast<uint32_t>(byte(a + 2)) << 16 | static_cast<uint32_t>(byte(a + 3)) << 24);
  };
  std::vector<FlashParam> out;
  for (int i = 0; i < kMaxEntries; ++i) {
    const uint32_t e = table + static_cast<uint32_t>(i) * kEntryBytes;
    // SDCC's generic pointer: address low, high, upper; upper bits 7..6 = 00: program memory
    const uint32_t lo = byte(e), hi = byte(e + 1), up = byte(e + 2);
    if (lo == 0 && hi == 0 && up == 0) return out;
    const uint32_t at = (up & 0x3Fu) << 16 | hi << 8 | lo;
    if ((up & 0xC0u) != 0 || at >= kFlashBytes)
      throw std::runtime_error("hal_param_table entry " + std::to_string(i) + " names no string in flash");
    FlashParam p;
    for (uint32_t k = 0; k <= kNameMax; ++k) {
      const uint8_t c = byte(at + k);
      if (c == 0) break;
      if (k == kNameMax) throw std::runtime_error("hal_param_table entry " + std::to_string(i) + ": name too long");
      p.name.push_back(static_cast<char>(c));
    }
    p.min = i32(e + 3);
    p.max = i32(e + 7);
    p.def = i32(e + 11);
    out.push_back(p);
  }
  throw std::runtime_error("hal_param_table has no end within " + std::to_string(kMaxEntries) + " entries");
}

std::vector<uint8_t> params_eeprom(const std::vector<FlashParam>& table, const std::map<std::string, int32_t>& values) {
  if (values.size() > HP_BOARD_PARAMS_MAX)
    throw std::runtime_error(std::to_string(values.size()) + " parameters: the board's EEPROM holds " +
                             std::to_string(HP_BOARD_PARAMS_MAX));
  std::vector<uint8_t> ee{static_cast<uint8_t>(HP_BOARD_PARAMS_MAGIC), static_cast<uint8_t>(values.size())};
  for (const auto& [name, v] : values) {
    size_t index = 0;
    while (index < table.size() && table[index].name != name) ++index;
    if (index == table.size()) {
      std::string declared;
      for (const auto& p : table) declared += (declared.empty() ? "" : ", ") + p.name;
      throw std::runtime_error("parameter '" + name + "' is not declared by the program's .hex (it declares: " +
                               (declared.empty() ? "nothing" : declared) +
                               "): rebuild the .hex from the same sources as the native program");
    }
    ee.push_back(static_cast<uint8_t>(index));
    const uint32_t u = static_cast<uint32_t>(v);
    for (int k = 0; k < 4; ++k) ee.push_back(static_cast<uint8_t>(u >> (8 * k)));
  }
  return ee;
}

}  // namespace chainsim::pic
