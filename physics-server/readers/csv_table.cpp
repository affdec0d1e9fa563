// The CSV reader (csv_table.h).
#include "readers/csv_table.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "readers/safe_text.h"

namespace chainsim {
namespace {

// s without the spaces and tabs around it; *lead = how many were in front
std::string trim(const std::string& s, size_t* lead = nullptr) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  if (lead) *lead = a;
  return s.substr(a, b - a);
}

std::vector<CsvTable::Cell> split(const std::string& line) {
  std::vector<CsvTable::Cell> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    const std::string raw = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t lead = 0;
    CsvTable::Cell c;
    c.text = trim(raw, &lead);
    c.column = static_cast<int>(start + lead) + 1;
    out.push_back(c);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string unquote(const std::string& s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
  return s;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

CsvError::CsvError(const std::string& message) : std::runtime_error(shown_text_cut(message)) {}

CsvTable CsvTable::read_file(const std::string& path, const std::string& what, const CsvColumns& columns,
                             CsvOptions options) {
  // a regular file of bounded size: not a FIFO (which would block), not
  // /dev/zero (which never ends)
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) throw CsvError(path + ": cannot open " + what);
  if (!std::filesystem::is_regular_file(st)) throw CsvError(path + ": " + what + " is not a regular file");
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size > kMaxFileBytes)
    throw CsvError(path + ": " + what + " is larger than " + std::to_string(kMaxFileBytes >> 20) + " MiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(path + ": cannot open " + what);
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<size_t>(in.gcount()));
  return parse(text, path, columns, options);
}

CsvTable CsvTable::parse(const std::string& text, const std::string& file, const CsvColumns& columns,
                         CsvOptions options) {
  CsvTable t;
  t.file_ = file;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    const std::string content = trim(line);
    if (content.empty() || (options.comments && content[0] == '#')) continue;
    std::vector<Cell> cells = split(line);
    if (t.header_line_ == 0) {
      t.header_line_ = lineno;
      std::set<std::string> seen;
      for (const Cell& c : cells) {
        const std::string name = unquote(c.text);
        if (!name.empty() && !seen.insert(name).second)
          t.fail(lineno, c.column, "column '" + name + "' appears twice in the header");
        t.names_.push_back(name);
      }
      for (const std::string& need : columns.needed)
        if (t.find(need) < 0)
          t.fail(lineno, 1,
                 "missing column '" + need + "' in the header (the header has: " + join(t.names_) +
                     "; needed: " + join(columns.needed) +
                     (columns.optional.empty() ? "" : "; optional: " + join(columns.optional)) + ")");
      continue;
    }
    if (cells.size() > t.names_.size())
      t.fail(lineno, cells[t.names_.size()].column,
             "this row has " + std::to_string(cells.size()) + " cells, the header " +
                 std::to_string(t.names_.size()));
    t.rows_.push_back({lineno, static_cast<int>(line.size()), std::move(cells)});
  }
  t.last_line_ = lineno;
  if (t.header_line_ == 0)
    t.fail(1, 1, "empty file: expected a header line naming the columns " + join(columns.needed));
  if (t.rows_.empty()) t.fail(lineno, 1, "no rows of data after the header");
  return t;
}

int CsvTable::find(const std::string& name) const {
  for (size_t k = 0; k < names_.size(); ++k)
    if (names_[k] == name) return static_cast<int>(k);
  return -1;
}

int CsvTable::column(const std::string& name) const {
  const int c = find(name);
  if (c < 0) fail(header_line_, 1, "missing column '" + name + "' in the header");
  return c;
}

const CsvTable::Cell& CsvTable::cell(size_t r, int c) const {
  const Row& row = rows_[r];
  if (c < 0 || c >= static_cast<int>(row.cells.size()))
    fail(row.line, row.length + 1,
         "missing column '" + (c >= 0 ? names_[c] : std::string("?")) + "' (this row has " +
             std::to_string(row.cells.size()) + " cells)");
  return row.cells[c];
}

bool CsvTable::blank(size_t r, int c) const {
  const Row& row = rows_[r];
  return c < 0 || c >= static_cast<int>(row.cells.size()) || row.cells[c].text.empty();
}

double CsvTable::number(size_t r, int c) const {
  const Cell& cl = cell(r, c);
  const std::string& name = names_[c];
  if (cl.text.empty()) fail_at(r, c, "empty cell in column '" + name + "'");
  char* end = nullptr;
  const double v = std::strtod(cl.text.c_str(), &end);
  if (end != cl.text.c_str() + cl.text.size())
    fail_at(r, c, "'" + cl.text + "' in column '" + name + "' is not a number");
  if (!std::isfinite(v)) fail_at(r, c, "'" + cl.text + "' in column '" + name + "' is not a finite number");
  return v;
}

void CsvTable::fail_at(size_t r, int c, const std::string& what) const {
  fail(rows_[r].line, cell(r, c).column, what);
}

void CsvTable::fail(int line, int column, const std::string& what) const {
  throw CsvError(file_ + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + what);
}

void CsvTable::fail_not_increasing(size_t r, int c) const {
  const std::string& name = names_[c];
  fail_at(r, c,
          name + " = " + cell(r, c).text + " is not after the previous row's " + cell(r - 1, c).text + " (line " +
              std::to_string(rows_[r - 1].line) + "): " + name + " must be strictly increasing");
}

}  // namespace chainsim
