// SHA-256 of a byte stream (OpenSSL's EVP), as lower-case hex: the trace's
// fingerprint in summary.json.
#pragma once

#include <cstddef>
#include <string>

namespace chainsim {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(const void* data, size_t len);
  std::string hex();  // finishes; call once
 private:
  void* ctx_;
};

}  // namespace chainsim
