// The one reader of the project's CSV files (bench set-points, calibration
// measurements, speed tables, run traces): a header row names the columns,
// which are found by name in any order; every error starts with
// "file:line:column: ". What it accepts:
//  - a UTF-8 byte-order mark, CRLF line ends, spaces and tabs around cells;
//  - header names in double quotes ("t_s"); a name given twice is an error;
//  - blank lines anywhere; lines starting with '#' when comments are on;
//  - a row may not have more cells than the header; a short row is an error
//    naming the first column it lacks, when that column is read.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

// its message is shown_text_cut: a cell quoted in it is escaped and bounded
class CsvError : public std::runtime_error {
 public:
  explicit CsvError(const std::string& message);
};

// the columns a file must have, and those it may have
struct CsvColumns {
  std::vector<std::string> needed;
  std::vector<std::string> optional;
};

struct CsvOptions {
  bool comments = false;  // skip lines whose first non-blank character is '#'
};

class CsvTable {
 public:
  static constexpr uintmax_t kMaxFileBytes = 32u << 20;  // a CSV file is a regular file of at most 32 MiB
  struct Cell {
    std::string text;  // without the spaces around it
    int column = 1;    // 1-based character column of its first character
  };
  struct Row {
    int line = 0;      // 1-based line number in the file
    int length = 0;    // characters on the line (for "missing column" at its end)
    std::vector<Cell> cells;
  };

  // reads the file; "file: cannot open <what>" when it cannot be read
  static CsvTable read_file(const std::string& path, const std::string& what, const CsvColumns& columns,
                            CsvOptions options = {});
  // parses text; `file` is used in messages. Needs a header with every
  // column in columns.needed and at least one row.
  static CsvTable parse(const std::string& text, const std::string& file, const CsvColumns& columns,
                        CsvOptions options = {});

  const std::string& file() const { return file_; }
  const std::vector<std::string>& names() const { return names_; }
  int header_line() const { return header_line_; }
  // the column of a name, or -1
  int find(const std::string& name) const;
  // the column of a needed name (it exists: parse checked it)
  int column(const std::string& name) const;

  size_t rows() const { return rows_.size(); }
  const Row& row(size_t r) const { return rows_[r]; }
  // line number of the last line of the file
  int last_line() const { return last_line_; }

  // the cell of row r in column c; "missing column 'name' (this row has N
  // cells)" at the end of the line when the row is short
  const Cell& cell(size_t r, int c) const;
  // true when the row lacks the column or its cell is blank
  bool blank(size_t r, int c) const;
  // the cell as a finite number (the whole cell, strtod syntax)
  double number(size_t r, int c) const;

  // "file:line:column: what" at the cell of row r in column c
  [[noreturn]] void fail_at(size_t r, int c, const std::string& what) const;
  // "file:line:column: what"
  [[noreturn]] void fail(int line, int column, const std::string& what) const;
  // the error for a column that must increase strictly, at row r (r > 0)
  [[noreturn]] void fail_not_increasing(size_t r, int c) const;

 private:
  std::string file_;
  std::vector<std::string> names_;
  int header_line_ = 0;
  int last_line_ = 0;
  std::vector<Row> rows_;
};

}  // namespace chainsim
