#include "optimize/checkpoint.h"

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "optimize/output_error.h"

namespace chainsim {

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  nlohmann::json best = {{"valid", c.best.valid},     {"generation", c.best.generation},
                         {"island", c.best.island},
                         {"individual", c.best.individual}, {"key", c.best.key},
                         {"genes", c.best.genes},     {"fitness", c.best.fitness},
                         {"failed", c.best.failed}};
  nlohmann::json islands = nlohmann::json::array();
  for (const auto& i : c.islands) {
    nlohmann::json f = nlohmann::json::array();
    for (double v : i.f) f.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(v > 0 ? "inf" : "-inf"));
    islands.push_back({{"genes", i.genes}, {"f", f}});
  }
  const nlohmann::json j = {{"format", 2},
                            {"fingerprint", c.fingerprint},
                            {"generation", c.generation},
                            {"islands", islands},
                            {"trials", c.trials},
                            {"trials_note", c.trials_note},
                            {"cache_keys", c.cache_keys},
                            {"history_bytes", c.history_bytes},
                            {"best", best},
                            {"evaluations", c.evaluations},
                            {"simulations", c.simulations},
                            {"cache_hits", c.cache_hits}};
  const std::string text = j.dump(1) + "\n";
  const std::string tmp = path + ".tmp";
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(tmp + ": cannot write: " + std::strerror(errno));
  bool ok = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ok = fsync(fd) == 0 && ok;  // the rename must not land before the bytes
  ok = close(fd) == 0 && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0)
    throw OutputError(path + ": cannot write: " + std::strerror(errno));
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError(path + ": cannot open (no search to resume here)");
  std::ostringstream s;
  s << in.rdbuf();
  Checkpoint c;
  try {
    const nlohmann::json j = nlohmann::json::parse(s.str());
    const int format = j.at("format").get<int>();
    if (format == 1)
      throw CheckpointError(path + ": written by an older chainsim (format 1): cannot resume; start the search "
                                   "again in another directory");
    if (format != 2) throw CheckpointError(path + ": unknown checkpoint format " + std::to_string(format));
    c.fingerprint = j.at("fingerprint").get<std::string>();
    c.generation = j.at("generation").get<int>();
    for (const auto& i : j.at("islands")) {
      Checkpoint::Island is;
      is.genes = i.at("genes").get<std::vector<std::vector<int64_t>>>();
      for (const auto& v : i.at("f")) {
        if (v.is_string()) is.f.push_back(v.get<std::string>() == "inf" ? HUGE_VAL : -HUGE_VAL);
        else is.f.push_back(v.get<double>());
      }
      if (is.genes.size() != is.f.size())
        throw CheckpointError(path + ": damaged: population and fitness differ in size");
      c.islands.push_back(is);
    }
    c.trials = j.at("trials").get<int>();
    c.trials_note = j.value("trials_note", std::string());
    c.cache_keys = j.at("cache_keys").get<std::vector<std::string>>();
    c.history_bytes = j.at("history_bytes").get<uint64_t>();
    const auto& b = j.at("best");
    c.best.valid = b.at("valid").get<bool>();
    c.best.generation = b.at("generation").get<int>();
    c.best.island = b.at("island").get<int>();
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
  return c;
}

void write_file_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(tmp + ": cannot write: " + std::strerror(errno));
  size_t done = 0;
  bool ok = true;
  while (ok && done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    ok = n > 0;
    if (ok) done += static_cast<size_t>(n);
  }
  const int err = ok ? 0 : errno;
  ok = close(fd) == 0 && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    unlink(tmp.c_str());
    throw OutputError(path + ": cannot write: " + std::strerror(err ? err : errno));
  }
}

}  // namespace chainsim
