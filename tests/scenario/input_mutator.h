// Malformed variants of a YAML input file (a scene or a module definition)
// for the fault-injection suite: one mutation of one kind per case, at a
// place and of a form the seed picks, so the same (text, kind, seed) always
// gives the same bytes.
#pragma once

#include <cstdint>
#include <string>

namespace scenario {

enum class MutationKind {
  DeleteKey,      // a key and what it holds
  DuplicateKey,   // a key given twice in its mapping
  ChangeType,     // a scalar becomes a list, a mapping, a bool, null, an alias...
  ExtremeNumber,  // nan, inf, 1e300, negative, zero, integers past 64 bits
  BadBytes,       // invalid UTF-8, NUL, control characters inside a key or value
  Truncate,       // the file cut at a byte offset
  SwapValues,     // two keys' values exchanged
  WrongNesting,   // a key moved one level in or out, a value wrapped, the file nested
  HugeList,       // lists of 50 000 values or 20 000 entries, nesting past any depth, aliases of 10^10
  MissingFile,    // a file the input refers to (mesh, module type, program) is not there
};
constexpr int kMutationKinds = 10;

const char* mutation_name(MutationKind kind);

struct Mutation {
  std::string text;          // the mutated file
  std::string what;          // what was changed where, one line, for a failure message
  bool drop_file = false;    // MissingFile of a file referred to from elsewhere: write nothing
};

// a mutation of `kind` of text; a kind that finds nothing to change (a file
// without numbers, say) cuts the file instead, and says so in `what`
Mutation mutate(const std::string& text, MutationKind kind, uint64_t seed);

// Malformed variants of a CSV record (a calibrate record: a measured servo
// record, a speed table), in the same way: '#' lines are comments, the first
// other line is the header
enum class CsvMutationKind {
  Truncate,        // the file cut at a byte offset
  BadBytes,        // invalid UTF-8, NUL, a control character inside a cell
  ExtremeNumber,   // nan, inf, 1e308, -1e308, 1e-320, a 30-digit integer in a cell
  TextCell,        // a number becomes text, "1,5" (one cell more), "0x10", "1e", a quoted cell
  DropColumn,      // a column removed: from the header only, or from every line
  DuplicateColumn, // a header name given twice (its column copied)
  RaggedRow,       // a row with a cell fewer or more
  RowOrder,        // two rows swapped, or one repeated: the key or time goes back or stands
  Oversize,        // past the bounds: 200 001 rows, a span of 10^6 s, a line of 2 MB
  Empty,           // nothing, a header alone, comments alone
};
constexpr int kCsvMutationKinds = 10;

const char* csv_mutation_name(CsvMutationKind kind);
Mutation mutate_csv(const std::string& text, CsvMutationKind kind, uint64_t seed);

// SplitMix64: a small generator whose sequence is the same everywhere
class SplitMix {
 public:
  explicit SplitMix(uint64_t seed) : s_(seed) {}
  uint64_t next() {
    uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // 0 .. n-1 (n > 0)
  size_t below(size_t n) { return static_cast<size_t>(next() % n); }

 private:
  uint64_t s_;
};

}  // namespace scenario
