// splitmix64: a counter-based mixing function (same input, same output, on
// every machine). Sensor noise draws from it per (seed, module, sensor,
// time), and the design search derives its run and generation seeds with it.
#pragma once

#include <cstdint>

namespace chainsim {

constexpr uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace chainsim
