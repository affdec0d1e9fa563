// A module type against the PIC board's pins. See pic_board.h.
#include "model/pic_board.h"

#include "hal_pic_board.h"

namespace chainsim {

std::vector<std::string> pic_board_misfits(const ModuleDef& def) {
  std::vector<std::string> out;
  const unsigned servos = static_cast<unsigned>(driven_servo_actuators(def).size());
  if (servos > HP_BOARD_SERVOS_MAX) {
    out.push_back(std::to_string(servos) + " servos: the board drives " + std::to_string(HP_BOARD_SERVOS_MAX));
    return out;
  }
  const unsigned adc = HP_BOARD_ADC_CHANNELS(servos), counters = HP_BOARD_COUNTERS(servos);
  const std::string with = "a module with " + std::to_string(servos) + " servo" + (servos == 1 ? "" : "s");
  for (const SensorDef& s : def.sensors) {
    const int last = s.channel + (s.type == SensorType::Accelerometer ? 2 : 0);
    switch (s.type) {
      case SensorType::MotorCurrent:
      case SensorType::Accelerometer:
        if (last >= static_cast<int>(adc))
          out.push_back("sensor '" + s.name + "' reads ADC channel" +
                        (last > s.channel ? "s " + std::to_string(s.channel) + ".." : " ") + std::to_string(last) +
                        ", but on the board " + with + " has ADC channels 0.." + std::to_string(adc - 1) +
                        " only (5 analog inputs AN0..AN4, the first " + std::to_string(servos) +
                        " taken by the servos' potentiometers)");
        break;
      case SensorType::Touch:
        if (s.channel + s.sectors > static_cast<int>(HP_BOARD_DIGITAL_INPUTS))
          out.push_back("sensor '" + s.name + "' is digital input" +
                        (s.sectors > 1 ? "s " + std::to_string(s.channel) + ".." : " ") +
                        std::to_string(s.channel + s.sectors - 1) +
                        ", but the board has digital inputs 0.." + std::to_string(HP_BOARD_DIGITAL_INPUTS - 1) +
                        " only (RB6, RB7, RC5, RC2)");
        break;
      case SensorType::WheelEncoder:
        if (s.channel >= static_cast<int>(counters))
          out.push_back("sensor '" + s.name + "' counts on counter " + std::to_string(s.channel) + ", but on the board " +
                        with + " has counters 0.." + std::to_string(counters - 1) +
                        " only (T13CKI; RB4 with at most 2 servos; INT2 without servos)");
        break;
    }
  }
  return out;
}

}  // namespace chainsim
