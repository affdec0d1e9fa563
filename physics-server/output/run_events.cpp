// Lines of events.jsonl. See run_events.h.
#include "output/run_events.h"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "text/number_text.h"

namespace chainsim {
namespace {

std::string head(int64_t t_us, const char* event) {
  return "{\"t_s\":" + seconds_text(t_us) + ",\"event\":\"" + event + "\"";
}

std::string quoted(const std::string& s) { return nlohmann::json(s).dump(); }

std::string list(const std::vector<int>& v) {
  std::string out = "[";
  for (size_t i = 0; i < v.size(); ++i) out += (i ? "," : "") + std::to_string(v[i]);
  return out + "]";
}

}  // namespace

std::string touch_event(int64_t t_us, int module, const std::string& sensor, bool contact) {
  return head(t_us, "touch") + ",\"module\":" + std::to_string(module) + ",\"sensor\":" + quoted(sensor) +
         ",\"contact\":" + (contact ? "true" : "false") + "}";
}

std::string address_event(int64_t t_us, int endpoint, const std::string& type, uint8_t address) {
  char hex[8];
  std::snprintf(hex, sizeof hex, "0x%02x", address);
  return head(t_us, "address") + ",\"endpoint\":" + std::to_string(endpoint) + ",\"type\":" + quoted(type) +
         ",\"address\":" + (address ? quoted(hex) : "null") + "}";
}

std::string discovery_event(int64_t t_us, const std::vector<int>& answered, const std::vector<int>& allowed_silent,
                            const std::vector<int>& silent) {
  return head(t_us, "discovery") + ",\"answered\":" + list(answered) + ",\"allowed_silent\":" +
         list(allowed_silent) + ",\"silent\":" + list(silent) + "}";
}

std::string fault_event(int64_t t_us, int endpoint, const std::string& type, const std::string& message) {
  if (endpoint < 0) return head(t_us, "fault") + ",\"endpoint\":null,\"type\":\"physics\",\"message\":" +
                           quoted(message) + "}";
  return head(t_us, "fault") + ",\"endpoint\":" + std::to_string(endpoint) + ",\"type\":" + quoted(type) +
         ",\"message\":" + quoted(message) + "}";
}

std::string queue_full_event(int64_t t_us, int endpoint, const std::string& type, int queued_bytes) {
  return head(t_us, "i2c_queue_full") + ",\"endpoint\":" + std::to_string(endpoint) + ",\"type\":" + quoted(type) +
         ",\"queued_bytes\":" + std::to_string(queued_bytes) + "}";
}

std::string warning_event(int64_t t_us, const std::string& message) {
  return head(t_us, "warning") + ",\"message\":" + quoted(message) + "}";
}

}  // namespace chainsim
