// A program's parameters as the PIC build keeps them: hal_param_table in
// flash (name, min, max, default; hal/hal_param.h with HAL_PARAM_NO_TEXT),
// and the data EEPROM image that gives some of them values
// (hal_pic_board.h, "parameters in the data EEPROM").
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim::pic {

struct FlashParam {
  std::string name;
  int32_t min = 0, max = 0, def = 0;
};

// the table at byte address `table` of flash, read with `byte(address)`:
// 15-byte entries (a 3-byte generic pointer to the name, three int32) up to
// the one whose name is null. Throws std::runtime_error on a table that is
// not one (a name outside flash, no end within 64 entries).
std::vector<FlashParam> read_param_table(uint32_t table, const std::function<uint8_t(uint32_t)>& byte);

// the EEPROM bytes that give `values` to the declared parameters; throws
// std::runtime_error naming a parameter the table does not declare, or when
// there are more than the EEPROM layout holds
std::vector<uint8_t> params_eeprom(const std::vector<FlashParam>& table, const std::map<std::string, int32_t>& values);

}  // namespace chainsim::pic
