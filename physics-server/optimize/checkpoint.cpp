#include "optimize/checkpoint.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace chainsim {

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  nlohmann::json best = {{"valid", c.best.valid},     {"generation", c.best.generation},
                         {"individual", c.best.individual}, {"key", c.best.key},
                         {"genes", c.best.genes},     {"fitness", c.best.fitness},
                         {"failed", c.best.failed}};
  const nlohmann::json j = {{"format", 1},
                            {"fingerprint", c.fingerprint},
                            {"generation", c.generation},
                            {"genes", c.genes},
                            {"f", c.f},
                            {"cache_keys", c.cache_keys},
                            {"history_bytes", c.history_bytes},
                            {"best", best},
                            {"evaluations", c.evaluations},
                            {"simulations", c.simulations},
                            {"cache_hits", c.cache_hits}};
  const std::string text = j.dump(1) + "\n";
  const std::string tmp = path + ".tmp";
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError(tmp + ": cannot write: " + std::strerror(errno));
  bool ok = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ok = fsync(fd) == 0 && ok;  // the rename must not land before the bytes
  ok = close(fd) == 0 && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0)
    throw CheckpointError(path + ": cannot write: " + std::strerror(errno));
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError(path + ": cannot open (no search to resume here)");
  std::ostringstream s;
  s << in.rdbuf();
  Checkpoint c;
  try {
    const nlohmann::json j = nlohmann::json::parse(s.str());
    if (j.at("format").get<int>() != 1) throw CheckpointError(path + ": unknown checkpoint format");
    c.fingerprint = j.at("fingerprint").get<std::string>();
    c.generation = j.at("generation").get<int>();
    c.genes = j.at("genes").get<std::vector<std::vector<int64_t>>>();
    c.f = j.at("f").get<std::vector<double>>();
    c.cache_keys = j.at("cache_keys").get<std::vector<std::string>>();
    c.history_bytes = j.at("history_bytes").get<uint64_t>();
    const auto& b = j.at("best");
    c.best.valid = b.at("valid").get<bool>();
    c.best.generation = b.at("generation").get<int>();
    c.best.individual = b.at("individual").get<size_t>();
    c.best.key = b.at("key").get<std::string>();
    c.best.genes = b.at("genes").get<std::vector<int64_t>>();
    c.best.fitness = b.at("fitness").get<double>();
    c.best.failed = b.at("failed").get<bool>();
    c.evaluations = j.at("evaluations").get<uint64_t>();
    c.simulations = j.at("simulations").get<uint64_t>();
    c.cache_hits = j.at("cache_hits").get<uint64_t>();
  } catch (const nlohmann::json::exception& e) {
    throw CheckpointError(path + ": damaged: " + e.what());
  }
  if (c.genes.size() != c.f.size()) throw CheckpointError(path + ": damaged: population and fitness differ in size");
  return c;
}

}  // namespace chainsim
