// The board around the chip. See pic_module.h.
#include "pic-module/pic_module.h"

#include <algorithm>
#include <cstdio>
#include <ctime>

#include "hal_pic_board.h"
#include "pic-module/param_table.h"
#include "text/number_text.h"

namespace chainsim::pic {

double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

namespace {

constexpr uint64_t kCyclesPerUs = HP_BOARD_FCY_HZ / 1000000;
constexpr uint8_t kPaint = 0xA5;  // the software stack's RAM before the program runs
constexpr uint32_t kSSPCON1 = 0xFC6, kSSPSTAT = 0xFC7, kSSPADD = 0xFC8;

// the potentiometer's counts for a servo's measured position (wire units:
// millidegrees; -90..+90 degrees span MIN..MAX counts), as a real number:
// the ADC rounds it
double pot_counts(int32_t wire) {
  const double c = HP_BOARD_POT_MIN_COUNTS +
                   (wire + 90000.0) * (HP_BOARD_POT_MAX_COUNTS - HP_BOARD_POT_MIN_COUNTS) / 180000.0;
  return std::clamp(c, 0.0, 1023.0);
}

// the voltage that the 10-bit converter (Vref 5 V) reads as `counts`
double volts_for(double counts) { return counts * 5.0 / 1023.0; }

}  // namespace

PicModule::PicModule(GpsimChip* chip, const PicBuild* build, const PicOptions& options)
    : chip_(chip),
      build_(build),
      opt_(options),
      meter_(CpuMeter::flags_for(*build, chip->flash_bytes(), [chip](uint32_t a) { return chip->programmed(a); })),
      uart_(static_cast<double>(HP_BOARD_FCY_HZ) / HP_BOARD_BAUD, CS_LOG_LINE_MAX - 1) {
  meter_.set_budget(opt_.budget_us * kCyclesPerUs);
  // gpsim 0.31's MSSP (the PIC18F2550's) does not stretch the clock after a
  // byte it receives as a slave, as the part does with SEN set (hal-pic sets
  // it): the bus beside it holds the clock instead while the byte sits
  // unread (SSPSTAT.BF). Without it an interrupt that came late read the
  // frame's last byte after the stop, as an address, and lost it.
  i2c_.set_clock_held([chip] {
    const unsigned mode = chip->ram(kSSPCON1) & 0x0Fu;
    const bool slave = mode == 0x6 || mode == 0x7 || mode == 0xE || mode == 0xF;
    return slave && (chip->ram(kSSPSTAT) & 0x01u);
  });
  meter_.set_metering(build->code_at("_next_tick") >= 0 && build->code_at("_hal_tick_wait") >= 0);
  // paint the software stack: how much of it the program ever used shows at the end
  const auto lo = build->data.find("_stack"), hi = build->data.find("_stack_end");
  if (lo != build->data.end() && hi != build->data.end() && hi->second > lo->second) {
    stack_lo_ = lo->second;
    stack_hi_ = hi->second;
    for (uint32_t a = stack_lo_; a <= stack_hi_; ++a) chip_->set_ram(a, kPaint);
  }
}

void PicModule::give_params(const std::map<std::string, int32_t>& values) {
  if (values.empty()) return;
  const int64_t table = build_->code_at("_hal_param_table");
  if (table < 0) throw std::runtime_error(build_->map + " has no hal_param_table: the program declares no parameters");
  const auto decl = read_param_table(static_cast<uint32_t>(table), [this](uint32_t a) { return chip_->flash_byte(a); });
  const auto ee = params_eeprom(decl, values);
  for (size_t i = 0; i < ee.size(); ++i) chip_->set_eeprom(static_cast<uint32_t>(i), ee[i]);
}

void PicModule::wire(const cs_tick_begin& tb) {
  servos_ = tb.n_servos;
  if (build_->servos >= 0 && build_->servos != servos_)
    throw std::runtime_error(build_->hex + " was built for " + std::to_string(build_->servos) +
                             " servo outputs (PIC_SERVOS); this module has " + std::to_string(servos_) +
                             ": rebuild it with PIC_SERVOS " + std::to_string(servos_));
  adc_ = std::min<int>(tb.n_adc, static_cast<int>(HP_BOARD_ADC_CHANNELS(static_cast<unsigned>(servos_))));
  counters_ = std::min<int>(tb.n_counters, static_cast<int>(HP_BOARD_COUNTERS(static_cast<unsigned>(servos_))));
  for (int i = 0; i < servos_; ++i) {
    chip_->line(static_cast<int>(HP_BOARD_SERVO_PULSE_PIN(i)), kServo0 + i, this);
    pot_[i] = chip_->line(static_cast<int>(HP_BOARD_AN_PIN(static_cast<unsigned>(i))), -1, nullptr);
  }
  for (int k = 0; k < adc_; ++k)
    adc_pin_[k] = chip_->line(static_cast<int>(HP_BOARD_AN_PIN(static_cast<unsigned>(servos_ + k))), -1, nullptr);
  for (unsigned d = 0; d < HP_BOARD_DIGITAL_INPUTS; ++d)
    digital_[d] = chip_->line(static_cast<int>(HP_BOARD_DIGITAL_PIN(d)), -1, nullptr);
  for (int c = 0; c < counters_; ++c) {
    counter_pin_[c] = chip_->line(static_cast<int>(HP_BOARD_COUNTER_PIN(static_cast<unsigned>(c))), -1, nullptr);
    counter_pin_[c]->drive_logic(false);
  }
  sin_ = chip_->line(HP_BOARD_SIN_PIN, -1, nullptr);
  sout_ = chip_->line(HP_BOARD_SOUT_PIN, kSout, this);
  tx_ = chip_->line(HP_BOARD_TX_PIN, kTx, this);
  scl_ = chip_->line(HP_BOARD_SCL_PIN, kScl, this, true);
  sda_ = chip_->line(HP_BOARD_SDA_PIN, kSda, this, true);
  scl_level_ = scl_->high();
  sda_level_ = sda_->high();
  wired_ = true;
}

void PicModule::edge(int id, uint64_t cycle, bool high) {
  if (id >= kServo0 && id < kServo0 + 4) pulses_[static_cast<size_t>(id - kServo0)].edge(cycle, high);
  else if (id == kTx) uart_.edge(cycle, high);
  else if (id == kScl || id == kSda) i2c_edges_.push_back({id, cycle, high});
}

void PicModule::drive_i2c() {
  if (i2c_.scl_low() != scl_driven_) {
    scl_driven_ = i2c_.scl_low();
    scl_driven_ ? scl_->drive(0.0) : scl_->release();
  }
  if (i2c_.sda_low() != sda_driven_) {
    sda_driven_ = i2c_.sda_low();
    sda_driven_ ? sda_->drive(0.0) : sda_->release();
  }
}

void PicModule::drain_edges() {
  // driving a line makes edges of its own: go on until the lines are quiet
  for (int rounds = 0; !i2c_edges_.empty() && rounds < 64; ++rounds) {
    std::vector<Edge> edges;
    edges.swap(i2c_edges_);
    for (const Edge& e : edges) {
      (e.id == kScl ? scl_level_ : sda_level_) = e.high;
      i2c_.lines(e.cycle, scl_level_, sda_level_);
      drive_i2c();
    }
  }
}

void PicModule::apply_inputs(const cs_tick_begin& tb, uint64_t from, uint64_t span) {
  for (unsigned d = 0; d < HP_BOARD_DIGITAL_INPUTS; ++d) digital_[d]->drive_logic((tb.digital_in >> d) & 1u);
  for (int i = 0; i < servos_; ++i) pot_[i]->drive(volts_for(pot_counts(tb.servo_pos[i])));
  for (int k = 0; k < adc_; ++k) adc_pin_[k]->drive(volts_for(tb.adc[k]));
  for (int c = 0; c < counters_; ++c) trains_[c].tick(tb.counter[c], from, span);
  for (unsigned f = 0; f < tb.n_i2c; ++f) i2c_.deliver(tb.i2c[f]);
  const bool sin = tb.sin_level != 0;
  if (sin != sin_level_ && tb.n_i2c > 0) {
    // the sender's frames went out before its Sout changed (hal-pic flushes
    // I2C before Sout): the chip gets them first, then the edge
    sin_pending_ = true;
    sin_after_ = i2c_.finished() + i2c_.waiting();
  } else if (!sin_pending_) {
    sin_->drive_logic(sin);
  }
  sin_level_ = sin;
  drain_edges();
}

std::string PicModule::run_until(uint64_t end) {
  for (;;) {
    drain_edges();
    if (sin_pending_ && i2c_.finished() >= sin_after_) {
      sin_pending_ = false;
      sin_->drive_logic(sin_level_);
      continue;
    }
    uint64_t now = chip_->cycle();
    if (i2c_.next_action() <= now) {
      i2c_.act(now);
      drive_i2c();
      continue;
    }
    bool acted = false;
    for (int c = 0; c < counters_; ++c) {
      if (trains_[c].next_action() <= now) {
        trains_[c].act(now);
        counter_pin_[c]->drive_logic(trains_[c].high());
        acted = true;
      }
    }
    if (acted) continue;
    if (now >= end) return "";
    uint64_t until = std::min(end, i2c_.next_action());
    for (int c = 0; c < counters_; ++c) until = std::min(until, trains_[c].next_action());
    const double cpu0 = thread_cpu_s();
    const GpsimChip::Stop stop = chip_->run(until, &meter_);
    gpsim_cpu_s_ += thread_cpu_s() - cpu0;
    if (stop == GpsimChip::Stop::Reset) {
      const GpsimChip::ResetCause r = chip_->reset_cause();
      std::string s = fault_at("the chip reset: " + r.what, r.pc);
      if (!r.calls.empty()) {
        // the return addresses, innermost first, a run of one function told once with its count
        s += "; called from";
        std::string last;
        int n = 0;
        auto flush = [&] {
          if (n) s += (s.back() == 'm' ? " " : ", ") + last + "()" + (n > 1 ? " x" + std::to_string(n) : "");
        };
        for (size_t i = r.calls.size(); i-- > 0;) {
          // a return address follows its call: the caller holds the word before it
          const std::string f = build_->function_at(r.calls[i] - 2);
          if (f == last) {
            ++n;
            continue;
          }
          flush();
          last = f;
          n = 1;
        }
        flush();
      }
      return s;
    }
    if (stop == GpsimChip::Stop::Outside)
      return fault_at("the chip executed outside its program (a jump through a bad pointer, or a return to a "
                      "corrupted address)", chip_->pc_at_stop());
    if (stop == GpsimChip::Stop::Overrun) {
      const std::string what = "a step of the program took more than its CPU budget of " +
                               std::to_string(opt_.budget_us) + " us of busy time (the step began at t=" +
                               fixed_text(static_cast<double>(meter_.step_began()) / HP_BOARD_FCY_HZ, 6) + " s)";
      if (!opt_.overrun_warn) return fault_at(what, chip_->pc_at_stop());
      ++overrun_warnings_;
      notes_.push_back("warning: " + what);
    }
  }
}

std::string PicModule::where(uint32_t pc) {
  char addr[16];
  std::snprintf(addr, sizeof addr, "0x%04X", pc);
  std::string s = std::string("at ") + addr + " in " + build_->function_at(pc) + "()";
  std::string file;
  int line = 0;
  chip_->asm_line(pc, &file, &line);
  // the .cod keeps 63 characters of a file name (a deep build folder's are
  // cut): the map names the assembly file in full
  const std::string from_map = build_->asm_file_at(pc);
  if (!from_map.empty()) file = from_map;
  SourceLines::Where w;
  if (line > 0 && !file.empty() && source_.find(file, line, &w))
    s += ", " + w.file + ":" + std::to_string(w.line) + " (" + w.text + ")";
  return s;
}

std::string PicModule::fault_at(const std::string& what, uint32_t pc) {
  return what + ", " + where(pc) + ", at t=" + fixed_text(static_cast<double>(chip_->cycle()) / HP_BOARD_FCY_HZ, 6) + " s";
}

uint8_t PicModule::address() {
  const unsigned mode = chip_->ram(kSSPCON1) & 0x0Fu;
  if (mode == 0x6 || mode == 0x7 || mode == 0xE || mode == 0xF)  // I2C slave modes
    addr_ = static_cast<uint8_t>(chip_->ram(kSSPADD) >> 1);
  return addr_;
}

std::string PicModule::tick(const cs_tick_begin& tb, uint32_t tick_us, cs_tick_end* te) {
  if (!wired_) wire(tb);
  now_us_ = tb.time_us;
  const uint64_t from = tb.time_us * kCyclesPerUs, end = (tb.time_us + tick_us) * kCyclesPerUs;
  apply_inputs(tb, from, end - from);
  std::string fault = run_until(end);
  const uint64_t now = chip_->cycle();
  // a step that has gone on for stall_ms, nearly all of it busy, never waits
  const uint64_t stall = opt_.stall_ms * 1000 * kCyclesPerUs;
  if (fault.empty() && meter_.metering() && now - meter_.step_began() > stall && meter_.step_busy() > stall * 9 / 10)
    fault = fault_at("the program has been busy for " + std::to_string(opt_.stall_ms) +
                     " ms without a HAL wait (on the board only a watchdog would end it)", chip_->pc());
  uart_.advance(now);

  *te = cs_tick_end{};
  te->wake_time_us = tb.time_us + tick_us;
  te->wake_events = 0;
  te->sout_level = sout_->high() ? 1 : 0;
  te->i2c_address = address();
  te->n_servos = static_cast<uint8_t>(servos_);
  for (int i = 0; i < servos_; ++i) {
    if (pulses_[i].driven(now)) te->servo_enable |= static_cast<uint8_t>(1u << i);
    te->servo_setpoint[i] = pulses_[i].setpoint_wire();
  }
  for (auto& f : i2c_.take_sent()) {
    ++frames_from_chip_;
    out_frames_.push_back(f);
  }
  size_t n = std::min<size_t>(out_frames_.size(), CS_I2C_FRAMES_MAX);
  for (size_t i = 0; i < n; ++i) te->i2c[i] = out_frames_[i];
  te->n_i2c = static_cast<uint8_t>(n);
  out_frames_.erase(out_frames_.begin(), out_frames_.begin() + static_cast<long>(n));
  while (uart_.has_line() && te->n_log < CS_LOG_LINES_MAX) {
    const std::string l = uart_.pop_line();
    std::snprintf(te->log[te->n_log++], CS_LOG_LINE_MAX, "%s", l.c_str());
    ++log_lines_;
  }
  for (auto& s : i2c_.take_notes()) notes_.push_back(s);
  return fault;
}

std::vector<std::string> PicModule::take_notes() { return std::exchange(notes_, {}); }

nlohmann::json PicModule::stats() const {
  const CpuStats& s = meter_.stats();
  nlohmann::json cpu;
  if (meter_.metering()) {
    const double steps = static_cast<double>(std::max<uint64_t>(s.steps, 1));
    cpu = {{"steps", s.steps},
           {"busy_mean_us", s.steps ? static_cast<double>(s.busy_sum) / steps / kCyclesPerUs : 0.0},
           {"busy_worst_us", static_cast<double>(s.busy_worst) / kCyclesPerUs},
           {"worst_step_at_s", static_cast<double>(s.worst_at) / HP_BOARD_FCY_HZ},
           {"period_mean_us", s.steps ? static_cast<double>(s.period_sum) / steps / kCyclesPerUs : 0.0},
           {"load", s.cycles ? static_cast<double>(s.busy_total) / static_cast<double>(s.cycles) : 0.0},
           {"startup_us", static_cast<double>(s.startup_cycles) / kCyclesPerUs},
           {"budget_us", opt_.budget_us ? nlohmann::json(opt_.budget_us) : nlohmann::json(nullptr)},
           {"overruns", s.overruns}};
  }
  uint32_t used = 0;
  if (stack_hi_ > stack_lo_) {
    uint32_t a = stack_lo_;
    while (a <= stack_hi_ && chip_->ram(a) == kPaint) ++a;
    used = stack_hi_ + 1 - a;
  }
  nlohmann::json j = {
      {"program", build_->hex},
      {"cycles", chip_->cycle()},
      {"cpu", cpu},
      {"stack", {{"hardware_levels_high", chip_->hw_stack_high()}, {"hardware_levels", 31},
                 {"software_bytes_high", used}, {"software_bytes", stack_hi_ > stack_lo_ ? stack_hi_ + 1 - stack_lo_ : 0}}},
      {"memory", {{"flash_bytes", build_->flash_bytes}, {"flash_total", build_->flash_total},
                  {"ram_bytes", build_->ram_bytes}, {"ram_total", build_->ram_total}}},
      {"pins", {{"frames_to_chip", i2c_.delivered()}, {"frames_from_chip", frames_from_chip_},
                {"log_lines", log_lines_}, {"uart_framing_errors", uart_.framing_errors()},
                {"servo_glitches", [this] { uint64_t g = 0; for (const auto& p : pulses_) g += p.glitches(); return g; }()},
                {"servo_pulses", [this] {
                   nlohmann::json n = nlohmann::json::array();
                   for (int i = 0; i < servos_; ++i) n.push_back(pulses_[static_cast<size_t>(i)].pulses());
                   return n;
                 }()},
                {"overrun_warnings", overrun_warnings_}}},
      // wall-clock and CPU figures of this machine: they vary from run to run
      {"host", {{"gpsim_cpu_s", gpsim_cpu_s_}, {"bridge_cpu_s", std::max(0.0, tick_cpu_s_ - gpsim_cpu_s_)},
                {"server_wait_s", server_wait_s_},
                {"cycles_per_cpu_s", gpsim_cpu_s_ > 0 ? static_cast<double>(chip_->cycle()) / gpsim_cpu_s_ : 0.0}}}};
  return j;
}

}  // namespace chainsim::pic
