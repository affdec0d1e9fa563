// The CSV reader: what it accepts (columns by name, quoted header names, BOM,
// CRLF, blank and comment lines) and the errors it gives (file:line:column).
#include "readers/csv_table.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace chainsim {
namespace {

const CsvColumns kTimeSeries{{"t_s", "v"}, {"w"}};

std::string error_of(const std::string& text, const CsvColumns& cols = kTimeSeries, CsvOptions opt = {}) {
  try {
    CsvTable::parse(text, "f.csv", cols, opt);
  } catch (const CsvError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string number_error(const std::string& text, size_t row, const std::string& column) {
  const CsvTable t = CsvTable::parse(text, "f.csv", kTimeSeries);
  try {
    t.number(row, t.find(column));
  } catch (const CsvError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CsvTable, ColumnsByNameInAnyOrderWithExtraColumns) {
  const CsvTable t = CsvTable::parse("note, v ,\"t_s\"\nx,2.5,0\ny,3,0.5\n", "f.csv", kTimeSeries);
  EXPECT_EQ(t.column("t_s"), 2);
  EXPECT_EQ(t.column("v"), 1);
  EXPECT_EQ(t.find("w"), -1);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.number(1, t.column("t_s")), 0.5);
  EXPECT_EQ(t.number(0, t.column("v")), 2.5);
  EXPECT_EQ(t.cell(1, 0).text, "y");
  EXPECT_EQ(t.row(1).line, 3);
}

TEST(CsvTable, ByteOrderMarkCrLfAndBlankLines) {
  const CsvTable t = CsvTable::parse("\xEF\xBB\xBFt_s,v\r\n0,1\r\n\r\n  \t\r\n1,2\r\n", "f.csv", kTimeSeries);
  EXPECT_EQ(t.names()[0], "t_s");
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.row(1).line, 5);
  EXPECT_EQ(t.number(1, 1), 2.0);
}

TEST(CsvTable, CommentLinesOnlyWhenAskedFor) {
  const std::string text = "# a table\nt_s,v\n0,1\n# a note\n1,2\n";
  const CsvTable t = CsvTable::parse(text, "f.csv", kTimeSeries, {.comments = true});
  EXPECT_EQ(t.header_line(), 2);
  EXPECT_EQ(t.rows(), 2u);
  EXPECT_NE(error_of(text).find("f.csv:1:1: missing column 't_s'"), std::string::npos) << error_of(text);
}

TEST(CsvTable, MissingColumnNamesWhatTheHeaderHasAndNeeds) {
  const std::string e = error_of("t_s,x\n0,1\n");
  EXPECT_NE(e.find("f.csv:1:1: missing column 'v' in the header (the header has: t_s, x; needed: t_s, v; "
                   "optional: w)"),
            std::string::npos)
      << e;
}

TEST(CsvTable, DuplicateHeaderNameIsAnError) {
  EXPECT_NE(error_of("t_s,v,t_s\n0,1,2\n").find("f.csv:1:7: column 't_s' appears twice"), std::string::npos);
}

TEST(CsvTable, EmptyFileAndHeaderOnly) {
  EXPECT_NE(error_of("").find("f.csv:1:1: empty file: expected a header line naming the columns t_s, v"),
            std::string::npos);
  EXPECT_NE(error_of("t_s,v\n\n").find("f.csv:2:1: no rows of data after the header"), std::string::npos)
      << error_of("t_s,v\n\n");
}

TEST(CsvTable, MalformedRowsNameLineAndColumn) {
  // a short row: the missing column at the end of the line
  EXPECT_NE(number_error("t_s,v\n0,1\n0.5\n", 1, "v").find("f.csv:3:4: missing column 'v' (this row has 1 cells)"),
            std::string::npos);
  // a long row: at its first extra cell
  EXPECT_NE(error_of("t_s,v\n0,1,2\n").find("f.csv:2:5: this row has 3 cells, the header 2"), std::string::npos)
      << error_of("t_s,v\n0,1,2\n");
  EXPECT_NE(number_error("t_s,v\n0,  3x\n", 0, "v").find("f.csv:2:5: '3x' in column 'v' is not a number"),
            std::string::npos);
  EXPECT_NE(number_error("t_s,v\n0,\n", 0, "v").find("f.csv:2:3: empty cell in column 'v'"), std::string::npos);
  EXPECT_NE(number_error("t_s,v\n0,inf\n", 0, "v").find("'inf' in column 'v' is not a finite number"),
            std::string::npos);
  // a quoted number is text, not a number
  EXPECT_NE(number_error("t_s,v\n0,\"1\"\n", 0, "v").find("is not a number"), std::string::npos);
}

TEST(CsvTable, NotIncreasingNamesBothRows) {
  const CsvTable t = CsvTable::parse("t_s,v\n0,1\n0.5,1\n0.5,2\n", "f.csv", kTimeSeries);
  try {
    t.fail_not_increasing(2, 0);
    FAIL() << "no error";
  } catch (const CsvError& e) {
    EXPECT_STREQ(e.what(),
                 "f.csv:4:1: t_s = 0.5 is not after the previous row's 0.5 (line 3): t_s must be strictly increasing");
  }
}

TEST(CsvTable, BlankReportsMissingAndEmptyCells) {
  const CsvTable t = CsvTable::parse("t_s,v,w\n0,1,\n1,2,3\n", "f.csv", kTimeSeries);
  EXPECT_TRUE(t.blank(0, 2));
  EXPECT_FALSE(t.blank(1, 2));
}

TEST(CsvTable, ReadsFilesAndNamesOnesThatCannotBeOpened) {
  const std::string path = testing::TempDir() + "/csv_table_test_" + std::to_string(getpid()) + ".csv";
  std::ofstream(path) << "t_s,v\n0,1\n";
  EXPECT_EQ(CsvTable::read_file(path, "the test file", kTimeSeries).rows(), 1u);
  std::remove(path.c_str());
  try {
    CsvTable::read_file(path, "the test file", kTimeSeries);
    FAIL() << "no error";
  } catch (const CsvError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot open the test file");
  }
}

// a file that is not a regular one is refused before it is read: /dev/zero
// would never end, a FIFO would block
TEST(CsvTable, OnlyRegularFilesOfBoundedSizeAreRead) {
  auto error = [](const std::string& path) {
    try {
      CsvTable::read_file(path, "the test file", kTimeSeries);
    } catch (const CsvError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error("/dev/zero"), "/dev/zero: the test file is not a regular file");
  const std::string fifo = testing::TempDir() + "/csv_table_test_" + std::to_string(getpid()) + ".fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(error(fifo), fifo + ": the test file is not a regular file");
  std::remove(fifo.c_str());
  const std::string big = testing::TempDir() + "/csv_table_test_big_" + std::to_string(getpid()) + ".csv";
  { std::ofstream(big) << "t_s,v\n"; }
  ASSERT_EQ(truncate(big.c_str(), static_cast<off_t>(CsvTable::kMaxFileBytes) + 1), 0);
  EXPECT_EQ(error(big), big + ": the test file is larger than 32 MiB");
  std::remove(big.c_str());
}

// a message quoting a cell shows it escaped and cut: a raw byte never
// reaches the terminal, a huge cell never floods it
TEST(CsvTable, AMessageQuotingACellIsEscapedAndBounded) {
  const std::string huge(100000, 'x');
  const std::string e = number_error("t_s,v\n0," + huge + "\n", 0, "v");
  EXPECT_LT(e.size(), 800u) << e.size();
  EXPECT_NE(e.find("bytes in all)"), std::string::npos) << e.substr(0, 200);
  const std::string raw = number_error("t_s,v\n0,\xFF\x1b[2J\n", 0, "v");
  EXPECT_EQ(raw.find('\x1b'), std::string::npos) << raw;
  EXPECT_NE(raw.find("\\xFF"), std::string::npos) << raw;
}

}  // namespace
}  // namespace chainsim
