// A module type on the PIC18F2550 board: the channels its sensors and
// actuators need against the pins the board has (hal-pic/hal_pic_board.h,
// shared with hal-pic and chainsim-pic). A module whose target is pic cannot
// read an ADC channel the board lacks: on the chip it reads 0, silently, so a
// scene is refused instead (docs/pic-in-the-loop.md).
#pragma once

#include <string>
#include <vector>

#include "model/module_def.h"

namespace chainsim {

// what the board lacks for def, one sentence each (empty: it fits)
std::vector<std::string> pic_board_misfits(const ModuleDef& def);

}  // namespace chainsim
