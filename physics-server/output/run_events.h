// events.jsonl of a run directory: one JSON object per line, in time order,
// for what a program or a test looks for without parsing text logs: a touch
// sensor's contact, a module taking its I2C address, the judgement of
// discovery, a fault, a warning. Every line starts with "t_s" (simulated
// seconds, 6 decimals, as every other time of a run) and "event";
// docs/outputs.md lists the events and their fields. Fixed formats: the same
// run gives the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace chainsim {

// a touch sensor of module `module` changed: contact true/false
std::string touch_event(int64_t t_us, int module, const std::string& sensor, bool contact);
// endpoint took I2C address `address` (0: it gave its address up)
std::string address_event(int64_t t_us, int endpoint, const std::string& type, uint8_t address);
// discovery judged at t: which modules had an address, which had none and
// were allowed to, which had none and failed
std::string discovery_event(int64_t t_us, const std::vector<int>& answered, const std::vector<int>& allowed_silent,
                            const std::vector<int>& silent);
// a fault of an endpoint (endpoint < 0: of the physics, type ignored) and
// its message, as the run reports it
std::string fault_event(int64_t t_us, int endpoint, const std::string& type, const std::string& message);
// endpoint sent an I2C frame with queued_bytes of its own already waiting on
// the bus, past CS_I2C_TX_QUEUE_MAX: the frame was dropped (the first such
// frame of each endpoint)
std::string queue_full_event(int64_t t_us, int endpoint, const std::string& type, int queued_bytes);
// a warning that does not stop the run (--on-divergence=warn)
std::string warning_event(int64_t t_us, const std::string& message);

}  // namespace chainsim
