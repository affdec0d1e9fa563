// The evaluation cache: results by individual key, so an individual (a chain,
// a parameter set) is simulated once per search. Every simulated result is
// also appended to a journal file the moment it ends, so a search killed in
// the middle of a generation keeps the evaluations it finished; on resume they
// are taken from the journal instead of simulated again.
//
// Two views: the cache proper holds what earlier generations evaluated (what
// an uninterrupted search would know at that point: history rows say "cached"
// from it); the journal holds everything ever simulated, including the
// unfinished generation's results. Keeping them apart is what makes a resumed
// search's history the same as an uninterrupted one's.
#pragma once

#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "optimize/evaluation.h"

namespace chainsim {

struct CacheError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class EvalCache {
 public:
  // opens journal_path (created if missing) and reads the results it holds.
  // Its first line names the search (fingerprint): a journal of another
  // search is a CacheError. A torn last line (a kill while writing) is
  // dropped, any other bad line is a CacheError naming file:line.
  EvalCache(const std::string& journal_path, const std::string& fingerprint);
  ~EvalCache();
  EvalCache(const EvalCache&) = delete;
  EvalCache& operator=(const EvalCache&) = delete;

  // the cache proper: a result of an earlier generation, or null
  const EvalResult* find(const std::string& key) const;
  // a result in the journal (simulated before, maybe by an interrupted run), or null
  const EvalResult* journaled(const std::string& key) const;
  // appends a fresh result to the journal (flushed at once)
  void record(const std::string& key, const EvalResult& r);
  // puts a journaled result into the cache proper (end of its generation)
  void commit(const std::string& key);
  // the cache proper's keys, for the checkpoint; restore() rebuilds it from them
  std::vector<std::string> keys() const;
  void restore(const std::vector<std::string>& keys);
  size_t size() const { return cache_.size(); }

 private:
  void write_line(const std::string& line);  // appended and flushed at once
  std::string path_;
  FILE* journal_ = nullptr;
  std::map<std::string, EvalResult> journaled_;
  std::map<std::string, EvalResult> cache_;
};

}  // namespace chainsim
