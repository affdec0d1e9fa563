#include "optimize/eval_cache.h"

#include <unistd.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "optimize/output_error.h"

namespace chainsim {

EvalCache::EvalCache(const std::string& journal_path, const std::string& fingerprint) : path_(journal_path) {
  std::string text;
  {
    std::ifstream in(path_, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  size_t pos = 0, line_no = 0;
  bool have_header = false;
  while (pos < text.size()) {
    const size_t nl = text.find('\n', pos);
    const bool complete = nl != std::string::npos;
    const std::string line = text.substr(pos, complete ? nl - pos : std::string::npos);
    ++line_no;
    if (!complete) {
      // a last line without its newline is torn (a kill while writing): cut it off
      if (truncate(path_.c_str(), static_cast<off_t>(pos)) != 0)
        throw CacheError(path_ + ": cannot cut its torn last line: " + std::strerror(errno));
      break;
    }
    pos = nl + 1;
    if (line.empty()) continue;
    try {
      const nlohmann::json j = nlohmann::json::parse(line);
      if (line_no == 1) {
        if (j.at("fingerprint").get<std::string>() != fingerprint)
          throw CacheError(path_ + ": the evaluations of another search (another problem file, base scene or "
                                   "settings); use another --out");
        have_header = true;
        continue;
      }
      journaled_[j.at("key").get<std::string>()] = eval_result_from_json(j.at("result"));
    } catch (const nlohmann::json::exception& e) {
      throw CacheError(path_ + ":" + std::to_string(line_no) + ": not a journal line: " + e.what());
    }
  }
  journal_ = std::fopen(path_.c_str(), "ab");
  if (!journal_) throw CacheError(path_ + ": cannot open for writing: " + std::strerror(errno));
  if (!have_header) write_line(nlohmann::json{{"fingerprint", fingerprint}}.dump() + "\n");
}

void EvalCache::write_line(const std::string& line) {
  if (std::fwrite(line.data(), 1, line.size(), journal_) != line.size() || std::fflush(journal_) != 0)
    throw OutputError(path_ + ": cannot write: " + std::strerror(errno));
}

EvalCache::~EvalCache() {
  if (journal_) std::fclose(journal_);
}

const EvalResult* EvalCache::find(const std::string& key) const {
  const auto it = cache_.find(key);
  return it == cache_.end() ? nullptr : &it->second;
}

const EvalResult* EvalCache::journaled(const std::string& key) const {
  const auto it = journaled_.find(key);
  return it == journaled_.end() ? nullptr : &it->second;
}

void EvalCache::record(const std::string& key, const EvalResult& r) {
  journaled_[key] = r;
  write_line(nlohmann::json{{"key", key}, {"result", eval_result_to_json(r)}}.dump() + "\n");
}

void EvalCache::commit(const std::string& key) {
  const auto it = journaled_.find(key);
  if (it != journaled_.end()) cache_[key] = it->second;
}

std::vector<std::string> EvalCache::keys() const {
  std::vector<std::string> k;
  for (const auto& kv : cache_) k.push_back(kv.first);
  return k;
}

void EvalCache::restore(const std::vector<std::string>& keys) {
  cache_.clear();
  for (const auto& k : keys) {
    const auto it = journaled_.find(k);
    if (it == journaled_.end())
      throw CacheError(path_ + ": the checkpoint names evaluation '" + k + "', which the journal does not hold");
    cache_[k] = it->second;
  }
}

}  // namespace chainsim
