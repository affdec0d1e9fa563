#include "optimize/history.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "optimize/output_error.h"

namespace chainsim {

namespace {

constexpr size_t kFixedColumns = 13;  // every column but the measures

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

double parse_number(const std::string& s) {
  if (s.empty()) return std::numeric_limits<double>::quiet_NaN();
  return std::strtod(s.c_str(), nullptr);  // also reads inf and -inf
}

}  // namespace

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return q + "\"";
}

std::string history_number(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

std::string history_header(const std::vector<std::string>& measure_names) {
  std::string h = "generation,island,individual,genome,fitness,trials,fitness_sd,fitness_min,fitness_max";
  for (const auto& m : measure_names) h += "," + m;
  return h + ",fault,early_stop,cached,wall_s\n";
}

std::string history_line(const HistoryRow& r) {
  const EvalResult& e = r.result;
  std::string l = std::to_string(r.generation) + "," + std::to_string(r.island) + "," + std::to_string(r.individual) +
                  "," + csv_field(r.genome) + "," + history_number(e.fitness) + "," + std::to_string(e.trials) + "," +
                  history_number(e.fitness_sd) + "," + history_number(e.fitness_min) + "," +
                  history_number(e.fitness_max);
  for (double m : e.measures) l += "," + history_number(m);
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3f", e.wall_s);
  return l + "," + csv_field(e.why) + "," + csv_field(e.early_stop) + "," + (r.cached ? "yes" : "no") + "," + wall +
         "\n";
}

std::vector<HistoryRow> parse_history(const std::string& text, size_t n_measures, const std::string& source) {
  std::vector<HistoryRow> rows;
  std::istringstream in(text);
  std::string line;
  size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no == 1 || line.empty()) continue;
    const std::vector<std::string> f = split_csv(line);
    if (f.size() != kFixedColumns + n_measures)
      throw std::runtime_error(source + ":" + std::to_string(line_no) + ": " + std::to_string(f.size()) +
                               " fields, expected " + std::to_string(kFixedColumns + n_measures));
    HistoryRow r;
    r.generation = std::atoi(f[0].c_str());
    r.island = std::atoi(f[1].c_str());
    r.individual = static_cast<size_t>(std::atoll(f[2].c_str()));
    r.genome = f[3];
    r.result.fitness = parse_number(f[4]);
    r.result.trials = std::atoi(f[5].c_str());
    r.result.fitness_sd = parse_number(f[6]);
    r.result.fitness_min = parse_number(f[7]);
    r.result.fitness_max = parse_number(f[8]);
    for (size_t k = 0; k < n_measures; ++k) r.result.measures.push_back(parse_number(f[9 + k]));
    r.result.why = f[9 + n_measures];
    r.result.failed = !r.result.why.empty();
    r.result.early_stop = f[10 + n_measures];
    r.cached = f[11 + n_measures] == "yes";
    r.result.wall_s = parse_number(f[12 + n_measures]);
    rows.push_back(r);
  }
  return rows;
}

HistoryFile::HistoryFile(const std::string& path, const std::vector<std::string>& measure_names, bool resume,
                         uint64_t keep_bytes)
    : path_(path) {
  if (resume) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0 || static_cast<uint64_t>(st.st_size) < keep_bytes)
      throw std::runtime_error(path + ": shorter than the checkpoint says (" + std::to_string(keep_bytes) +
                               " bytes): cannot resume");
    {
      std::ifstream in(path);
      std::string first;
      std::getline(in, first);
      if (first + "\n" != history_header(measure_names))
        throw std::runtime_error(path + ": its columns are not this chainsim's (written by an older one?): "
                                 "cannot resume; start the search again in another directory");
    }
    if (truncate(path.c_str(), static_cast<off_t>(keep_bytes)) != 0)
      throw std::runtime_error(path + ": cannot cut to the checkpoint: " + std::strerror(errno));
    f_ = std::fopen(path.c_str(), "ab");
  } else {
    f_ = std::fopen(path.c_str(), "wb");
    if (f_) std::fputs(history_header(measure_names).c_str(), f_);
  }
  if (!f_) throw OutputError(path + ": cannot write: " + std::strerror(errno));
}

HistoryFile::~HistoryFile() {
  if (f_) std::fclose(f_);
}

void HistoryFile::append(const HistoryRow& row) { std::fputs(history_line(row).c_str(), f_); }

uint64_t HistoryFile::flush() {
  if (std::fflush(f_) != 0) throw OutputError(path_ + ": cannot write: " + std::strerror(errno));
  struct stat st {};
  if (fstat(fileno(f_), &st) != 0) throw std::runtime_error(path_ + ": cannot stat: " + std::strerror(errno));
  return static_cast<uint64_t>(st.st_size);
}

}  // namespace chainsim
