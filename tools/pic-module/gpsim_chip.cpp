// One PIC18F2550 in gpsim. See gpsim_chip.h.
#include "pic-module/gpsim_chip.h"

// gpsim's headers only compile in this order
#include <gpsim/interface.h>
#include <gpsim/sim_context.h>
#include <gpsim/processor.h>
#include <gpsim/pic-processor.h>
#include <gpsim/stimuli.h>
#include <gpsim/gpsim_time.h>
#include <gpsim/breakpoints.h>
#include <gpsim/eeprom.h>
#include <gpsim/14bit-registers.h>
#include <gpsim/symbol.h>
#include <gpsim/value.h>

#include <stdexcept>

#include "hal_pic_board.h"

namespace chainsim::pic {

namespace {

constexpr double kOpenOhm = 1e12;    // released: as good as no connection
constexpr double kDriveOhm = 100;    // a sensor's or a gate's output
constexpr double kPullUpOhm = 10e3;  // the I2C lines' pull-ups
constexpr double kThresholdV = 2.5;
constexpr uint32_t kSTKPTR = 0xFFC, kRCON = 0xFD0;

}  // namespace

// the outside world on one pin: a Thevenin source (open, or volts through
// 100 Ohm) that also hears every change of the node's voltage
class Source : public stimulus {
 public:
  Source(const std::string& name, GpsimChip* chip, EdgeSink* sink, int id)
      : stimulus(name.c_str(), 0.0, kOpenOhm), chip_(chip), sink_(sink), id_(id) {}
  void getThevenin(double& v, double& z, double& c) override {
    v = vth_;
    z = zth_;
    c = 0;
  }
  void set_nodeVoltage(double v) override {
    nodeVoltage = v;
    const bool h = v > kThresholdV;
    if (!known_) {
      known_ = true;
      level_ = h;
      return;
    }
    if (h == level_) return;
    level_ = h;
    if (sink_) {
      chip_->edge_ = true;
      sink_->edge(id_, get_cycles().get(), h);
    }
  }
  void set(double vth, double zth) {
    vth_ = vth;
    zth_ = zth;
    if (snode) snode->update();
  }
  bool level() const { return level_; }
  double volts() const { return nodeVoltage; }

 private:
  GpsimChip* chip_;
  EdgeSink* sink_;
  int id_;
  double vth_ = 0, zth_ = kOpenOhm;
  bool known_ = false, level_ = false;
};

class PullUp : public stimulus {
 public:
  explicit PullUp(const std::string& name) : stimulus(name.c_str(), 5.0, kPullUpOhm) {}
  void getThevenin(double& v, double& z, double& c) override {
    v = 5.0;
    z = kPullUpOhm;
    c = 0;
  }
};

PinLine::~PinLine() = default;
void PinLine::release() { src_->set(0.0, kOpenOhm); }
void PinLine::drive(double volts) { src_->set(volts, kDriveOhm); }
bool PinLine::high() const { return src_->level(); }
double PinLine::volts() const { return src_->volts(); }

GpsimChip::GpsimChip(const std::string& cod_path) {
  static bool core = false;
  if (core) throw std::logic_error("gpsim simulates one chip per process");
  core = true;
  initialize_gpsim_core();
  // gpsim would read every source file the .cod names, and can crash on a
  // name the .cod cut short (hal-pic/README.md); the lines it knows are enough
  if (auto* load_source = dynamic_cast<Boolean*>(globalSymbolTable().find("EnableSourceLoad")))
    load_source->set(false);
  if (!CSimulationContext::GetContext()->LoadProgram(cod_path.c_str(), "p18f2550", &cpu_) || !cpu_)
    throw std::runtime_error("gpsim could not load " + cod_path);
  pic_ = dynamic_cast<pic_processor*>(cpu_);
  if (!pic_) throw std::runtime_error("gpsim did not make a PIC of " + cod_path);
  cpu_->set_frequency(static_cast<double>(HP_BOARD_FOSC_HZ));
  cpu_->setBreakOnReset(true);  // a reset ends run(): the module process reports it
  get_bp().clear_global();
}

GpsimChip::~GpsimChip() = default;  // gpsim owns its nodes and stimuli until the process ends

PinLine* GpsimChip::line(int pin, int id, EdgeSink* sink, bool pull_up) {
  IOPIN* p = cpu_->get_pin(static_cast<unsigned>(pin));
  if (!p) throw std::runtime_error("the p18f2550 has no pin " + std::to_string(pin));
  const std::string name = "chainsim_pin" + std::to_string(pin);
  auto* node = new Stimulus_Node((name + "_node").c_str());
  node->attach_stimulus(p);
  auto* src = new Source(name, this, sink, id);
  node->attach_stimulus(src);
  if (pull_up) {
    pullups_.push_back(std::make_unique<PullUp>(name + "_pullup"));
    node->attach_stimulus(pullups_.back().get());
  }
  node->update();
  nodes_.push_back(node);
  lines_.push_back(std::unique_ptr<PinLine>(new PinLine()));
  lines_.back()->src_ = src;
  lines_.back()->node_ = node;
  return lines_.back().get();
}

uint64_t GpsimChip::cycle() const { return get_cycles().get(); }
uint32_t GpsimChip::pc() const { return cpu_->pc->value * 2; }

GpsimChip::Stop GpsimChip::run(uint64_t until, CpuMeter* meter) {
  Cycle_Counter& cyc = get_cycles();
  Breakpoints& bp = get_bp();
  Program_Counter* pc = cpu_->pc;
  Stack* stack = pic_->stack;
  edge_ = false;
  uint64_t now = cyc.get();
  while (now < until) {
    const uint32_t at = pc->value * 2;  // gpsim counts PIC18 program words; addresses are bytes
    const int depth = stack->pointer;   // before the step: an interrupt taken in it pushes
    cpu_->step_cycle();
    const uint64_t after = cyc.get();
    if (stack->pointer > hw_high_) hw_high_ = stack->pointer;
    if (bp.have_halt()) {
      last_pc_ = at;
      bp.clear_halt();
      return Stop::Reset;
    }
    if (after != now) {  // an interrupt's capture takes a step without a cycle
      now = after;
      const uint8_t f = meter->cycle(at, now, depth);
      if (f & (CpuMeter::kOutside | CpuMeter::kOverrun)) {
        last_pc_ = at;
        return (f & CpuMeter::kOutside) ? Stop::Outside : Stop::Overrun;
      }
    }
    if (edge_) return Stop::Edge;
  }
  return Stop::Reached;
}

GpsimChip::ResetCause GpsimChip::reset_cause() const {
  ResetCause r;
  r.pc = last_pc_;
  const unsigned stkptr = cpu_->rma[kSTKPTR].get_value();
  const unsigned rcon = cpu_->rma[kRCON].get_value();
  if (stkptr & 0x80u)
    r.what = "stack overflow: more than 31 calls and interrupts nested on the hardware return stack";
  else if (stkptr & 0x40u)
    r.what = "stack underflow: a return with nothing on the hardware return stack";
  else if (!(rcon & 0x10u))
    r.what = "a RESET instruction";
  else if (!(rcon & 0x08u))
    r.what = "the watchdog timer expired";
  else
    r.what = "a reset (RCON " + std::to_string(rcon) + ")";
  const int depth = hw_high_ < 31 ? hw_high_ : 31;
  for (int i = 0; i < depth; ++i) r.calls.push_back(pic_->stack->contents[i]);
  return r;
}

uint8_t GpsimChip::ram(uint32_t address) const { return static_cast<uint8_t>(cpu_->rma[address].get_value()); }
void GpsimChip::set_ram(uint32_t address, uint8_t value) { cpu_->rma[address].put_value(value); }
uint16_t GpsimChip::flash_word(uint32_t a) const { return static_cast<uint16_t>(cpu_->pma->get_rom(a & ~1u)); }
uint8_t GpsimChip::flash_byte(uint32_t a) const {
  const uint16_t w = flash_word(a);
  return static_cast<uint8_t>((a & 1u) ? w >> 8 : w & 0xFFu);
}
bool GpsimChip::programmed(uint32_t a) const { return cpu_->pma->hasValid_opcode_at_address(a); }
uint32_t GpsimChip::flash_bytes() const { return cpu_->program_memory_size() * 2; }
void GpsimChip::set_eeprom(uint32_t address, uint8_t value) { pic_->eeprom->change_rom(address, value); }

void GpsimChip::asm_line(uint32_t pc, std::string* file, int* line) const {
  file->clear();
  *line = 0;
  const int fid = cpu_->pma->get_file_id(pc);
  if (fid < 0 || fid >= cpu_->files.nsrc_files()) return;
  if (FileContext* fc = cpu_->files[fid]) {
    *file = fc->name();
    *line = cpu_->pma->get_src_line(pc);
  }
}

}  // namespace chainsim::pic
