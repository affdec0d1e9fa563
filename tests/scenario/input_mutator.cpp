// Malformed variants of YAML input files. See input_mutator.h. The files are
// edited as text, not as YAML, so that what no YAML writer would produce
// (duplicate keys, torn bytes, cut files) is produced too.
#include "input_mutator.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>
#include <vector>

namespace scenario {
namespace {

struct Span {
  size_t pos = 0, len = 0;
};

// a key of a block mapping: the line and where the key starts in it
struct KeyLine {
  size_t line = 0;
  size_t col = 0;    // after the indent and any "- "
  std::string key;
};

// a `key: value` with a plain scalar value, anywhere (block or flow)
struct Pair {
  Span key, value;
};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  size_t b = 0;
  while (b < text.size()) {
    const size_t e = text.find('\n', b);
    if (e == std::string::npos) {
      lines.push_back(text.substr(b));
      break;
    }
    lines.push_back(text.substr(b, e - b));
    b = e + 1;
  }
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

bool is_key_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// the column of a line's first character that is not a space; npos when blank or a comment
size_t content_col(const std::string& line) {
  const size_t c = line.find_first_not_of(' ');
  return c == std::string::npos || line[c] == '#' ? std::string::npos : c;
}

std::vector<KeyLine> key_lines(const std::vector<std::string>& lines) {
  std::vector<KeyLine> out;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    size_t c = content_col(l);
    if (c == std::string::npos) continue;
    while (c + 1 < l.size() && l[c] == '-' && l[c + 1] == ' ') c = l.find_first_not_of(' ', c + 1);
    if (c == std::string::npos || !(std::isalpha(static_cast<unsigned char>(l[c])) || l[c] == '_')) continue;
    size_t e = c;
    while (e < l.size() && is_key_char(l[e])) ++e;
    if (e < l.size() && l[e] == ':' && (e + 1 == l.size() || l[e + 1] == ' ')) out.push_back({i, c, l.substr(c, e - c)});
  }
  return out;
}

// the lines of key line k: itself and those nested deeper below it
size_t block_end(const std::vector<std::string>& lines, const KeyLine& k) {
  size_t e = k.line + 1;
  while (e < lines.size()) {
    const size_t c = content_col(lines[e]);
    if (c != std::string::npos && c <= k.col) break;
    ++e;
  }
  return e;
}

// whether pos is after a '#' on its line (a comment)
bool in_comment(const std::string& text, size_t pos) {
  const size_t line = text.rfind('\n', pos);
  const size_t from = line == std::string::npos ? 0 : line + 1;
  return text.find('#', from) < pos;
}

std::vector<Pair> scalar_pairs(const std::string& text) {
  std::vector<Pair> out;
  for (size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] != ':' || text[i + 1] != ' ' || i == 0 || !is_key_char(text[i - 1])) continue;
    size_t kb = i;
    while (kb > 0 && is_key_char(text[kb - 1])) --kb;
    size_t vb = i + 1;
    while (vb < text.size() && text[vb] == ' ') ++vb;
    if (vb >= text.size() || std::string("\n[]{},#'\"&*!|>").find(text[vb]) != std::string::npos) continue;
    size_t ve = vb;
    while (ve < text.size() && std::string("\n,[]{}#").find(text[ve]) == std::string::npos) ++ve;
    while (ve > vb && text[ve - 1] == ' ') --ve;
    if (ve == vb || in_comment(text, kb)) continue;
    out.push_back({{kb, i - kb}, {vb, ve - vb}});
  }
  return out;
}

std::vector<Span> numbers(const std::string& text) {
  std::vector<Span> out;
  const std::string before = " \t[,:{\n";
  const std::string after = " \t,]}\n";
  for (size_t i = 0; i < text.size(); ++i) {
    const bool digit = std::isdigit(static_cast<unsigned char>(text[i]));
    const bool minus = text[i] == '-' && i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1]));
    if (!(digit || minus) || (i > 0 && before.find(text[i - 1]) == std::string::npos)) continue;
    size_t e = i + 1;
    while (e < text.size() && std::string("0123456789.eE+-").find(text[e]) != std::string::npos) ++e;
    if ((e == text.size() || after.find(text[e]) != std::string::npos) && !in_comment(text, i)) out.push_back({i, e - i});
    i = e;
  }
  return out;
}

std::string replaced(const std::string& text, Span s, const std::string& with) {
  return text.substr(0, s.pos) + with + text.substr(s.pos + s.len);
}

std::string line_of(const std::string& text, size_t pos) {
  size_t n = 1;
  for (size_t i = 0; i < pos && i < text.size(); ++i) n += text[i] == '\n';
  return "line " + std::to_string(n);
}

template <size_t N>
const char* pick(SplitMix& r, const char* const (&options)[N]) {
  return options[r.below(N)];
}

using Result = Mutation;
const Result kNothing{};  // the kind found nothing to change

bool none(const Result& m) { return m.what.empty(); }

Result delete_key(const std::string& text, SplitMix& r) {
  const auto lines = split_lines(text);
  const auto keys = key_lines(lines);
  const auto pairs = scalar_pairs(text);
  if (!pairs.empty() && r.below(3) == 0) {  // a pair inside a flow mapping, or a block one's value
    const Pair p = pairs[r.below(pairs.size())];
    return {replaced(text, {p.key.pos, p.value.pos + p.value.len - p.key.pos}, ""),
            "deleted '" + text.substr(p.key.pos, p.key.len) + "' and its value at " + line_of(text, p.key.pos)};
  }
  if (keys.empty()) return kNothing;
  const KeyLine k = keys[r.below(keys.size())];
  std::vector<std::string> out(lines.begin(), lines.begin() + k.line);
  size_t e = block_end(lines, k);
  // a list entry's first key gives its dash to the next key, so the entry stays
  const std::string dash = lines[k.line].substr(0, k.col);
  if (dash.find('-') != std::string::npos && e < lines.size() && content_col(lines[e]) == k.col) {
    out.push_back(dash + lines[e].substr(k.col));
    ++e;
  }
  out.insert(out.end(), lines.begin() + e, lines.end());
  return {join_lines(out), "deleted key '" + k.key + "' (line " + std::to_string(k.line + 1) + ") and its block"};
}

Result duplicate_key(const std::string& text, SplitMix& r) {
  const auto lines = split_lines(text);
  const auto keys = key_lines(lines);
  const auto pairs = scalar_pairs(text);
  if (!pairs.empty() && (keys.empty() || r.below(2) == 0)) {
    const Pair p = pairs[r.below(pairs.size())];
    const size_t end = p.value.pos + p.value.len;
    const std::string kv = text.substr(p.key.pos, end - p.key.pos);
    // a flow pair gets a sibling after a comma; a block pair, a line of its own
    const bool flow = text.find('\n', p.key.pos) > text.find_first_of(",}", end) ||
                      text.find_first_of(",}", end) == std::string::npos;
    const size_t eol = std::min(text.find('\n', end), text.size());
    const size_t bol = text.rfind('\n', p.key.pos) == std::string::npos ? 0 : text.rfind('\n', p.key.pos) + 1;
    std::string out = text;
    if (flow && text.find_first_of(",}", end) < eol)
      out.insert(end, ", " + kv);
    else
      out.insert(eol, "\n" + std::string(p.key.pos - bol, ' ') + kv);
    return {out, "key '" + text.substr(p.key.pos, p.key.len) + "' given twice at " + line_of(text, p.key.pos)};
  }
  if (keys.empty()) return kNothing;
  const KeyLine k = keys[r.below(keys.size())];
  const size_t e = block_end(lines, k);
  std::vector<std::string> out(lines.begin(), lines.begin() + e);
  for (size_t i = k.line; i < e; ++i)
    out.push_back(i == k.line ? std::string(k.col, ' ') + lines[i].substr(k.col) : lines[i]);
  out.insert(out.end(), lines.begin() + e, lines.end());
  return {join_lines(out), "key '" + k.key + "' (line " + std::to_string(k.line + 1) + ") and its block given twice"};
}

Result change_type(const std::string& text, SplitMix& r) {
  const auto pairs = scalar_pairs(text);
  if (pairs.empty()) return kNothing;
  static const char* const kValues[] = {"[1, 2]", "{a: 1}", "true", "~", "''", "[]", "{}", "text",
                                        "!!binary aGVsbG8=", "&anchor 1", "*undefined_alias", "\"\\u0000\"",
                                        "[[1], [2, [3]]]", "|\n  a\n  b", "0x10", "2001-12-14"};
  const Pair p = pairs[r.below(pairs.size())];
  const std::string v = pick(r, kValues);
  return {replaced(text, p.value, v),
          "'" + text.substr(p.key.pos, p.key.len) + "' = " + v + " at " + line_of(text, p.key.pos)};
}

Result extreme_number(const std::string& text, SplitMix& r) {
  const auto spans = numbers(text);
  if (spans.empty()) return kNothing;
  static const char* const kValues[] = {".nan", ".NaN", ".inf", "-.inf", "1e300", "-1e300", "1e309", "-1", "0",
                                        "-0.0", "1e-300", "2147483648", "-2147483649", "9223372036854775808",
                                        "18446744073709551616", "0x7fffffff", "0o777", "1_000", "+12", "12.",
                                        ".5e3", "4.9e-324", "NEGATE"};
  const Span s = spans[r.below(spans.size())];
  std::string v = pick(r, kValues);
  const std::string old = text.substr(s.pos, s.len);
  if (v == "NEGATE") v = old[0] == '-' ? old.substr(1) : "-" + old;
  return {replaced(text, s, v), old + " -> " + v + " at " + line_of(text, s.pos)};
}

Result bad_bytes(const std::string& text, SplitMix& r) {
  const auto pairs = scalar_pairs(text);
  if (pairs.empty()) return kNothing;
  static const char* const kBytes[] = {"\xff", "\xc3\x28", "\xe2\x82", "\xf0\x28\x8c\x28", "\xc0\xaf",
                                       "\xed\xa0\x80", "\x1b[31m", "\x07", "\x7f", "\xc2\x85", "\xc2\x9b",
                                       "\r", "\x0b", "\xef\xbb\xbf", "\xe2\x80\xae", "\x01\x02"};
  const Pair p = pairs[r.below(pairs.size())];
  const Span in = r.below(2) ? p.key : p.value;
  const size_t at = in.pos + r.below(in.len + 1);
  std::string bytes = r.below(8) == 0 ? std::string(1, '\0') : std::string(pick(r, kBytes));
  std::string out = text;
  out.insert(at, bytes);
  std::string shown;
  for (unsigned char c : bytes) shown += "\\x" + std::string(1, "0123456789abcdef"[c >> 4]) + "0123456789abcdef"[c & 15];
  return {out, "bytes " + shown + " inserted at " + line_of(text, at)};
}

Result truncate(const std::string& text, SplitMix& r) {
  const size_t at = text.empty() ? 0 : r.below(text.size());
  return {text.substr(0, at), "cut at byte " + std::to_string(at) + " of " + std::to_string(text.size())};
}

Result swap_values(const std::string& text, SplitMix& r) {
  const auto pairs = scalar_pairs(text);
  if (pairs.size() < 2) return kNothing;
  const size_t i = r.below(pairs.size());
  size_t j = r.below(pairs.size() - 1);
  if (j >= i) ++j;
  Pair a = pairs[std::min(i, j)], b = pairs[std::max(i, j)];
  const std::string va = text.substr(a.value.pos, a.value.len), vb = text.substr(b.value.pos, b.value.len);
  std::string out = replaced(text, b.value, va);  // the later one first: the earlier offsets stay
  out = replaced(out, a.value, vb);
  return {out, "values of '" + text.substr(a.key.pos, a.key.len) + "' and '" + text.substr(b.key.pos, b.key.len) +
                   "' swapped (" + line_of(text, a.key.pos) + ", " + line_of(text, b.key.pos) + ")"};
}

Result wrong_nesting(const std::string& text, SplitMix& r) {
  auto lines = split_lines(text);
  const auto keys = key_lines(lines);
  const auto pairs = scalar_pairs(text);
  switch (r.below(4)) {
    case 0:
      if (keys.empty()) return kNothing;
      {
        const KeyLine k = keys[r.below(keys.size())];
        lines[k.line].insert(0, "  ");
        return {join_lines(lines), "key '" + k.key + "' (line " + std::to_string(k.line + 1) + ") indented one level in"};
      }
    case 1: {
      std::vector<KeyLine> nested;
      for (const auto& k : keys)
        if (k.col >= 2 && lines[k.line].compare(0, 2, "  ") == 0) nested.push_back(k);
      if (nested.empty()) return kNothing;
      const KeyLine k = nested[r.below(nested.size())];
      lines[k.line].erase(0, 2);
      return {join_lines(lines), "key '" + k.key + "' (line " + std::to_string(k.line + 1) + ") moved one level out"};
    }
    case 2: {
      if (pairs.empty()) return kNothing;
      const Pair p = pairs[r.below(pairs.size())];
      const std::string key = text.substr(p.key.pos, p.key.len), value = text.substr(p.value.pos, p.value.len);
      return {replaced(text, p.value, "{" + key + ": " + value + "}"),
              "value of '" + key + "' wrapped in a mapping at " + line_of(text, p.key.pos)};
    }
    default: {
      std::string out = "scene:\n";
      for (const auto& l : lines) out += "  " + l + "\n";
      return {out, "the whole file nested under a key"};
    }
  }
}

Result huge_list(const std::string& text, SplitMix& r) {
  const auto pairs = scalar_pairs(text);
  switch (r.below(4)) {
    case 0: {
      if (pairs.empty()) return kNothing;
      const Pair p = pairs[r.below(pairs.size())];
      std::string list = "[0";
      for (int i = 1; i < 50000; ++i) list += ", 0";
      return {replaced(text, p.value, list + "]"),
              "'" + text.substr(p.key.pos, p.key.len) + "' = a list of 50000 zeros at " + line_of(text, p.key.pos)};
    }
    case 1: {
      const size_t depth = 2000 + r.below(20000);
      return {std::string(depth, '[') + std::string(depth, ']') + "\n" + text,
              "a list nested " + std::to_string(depth) + " deep before the file"};
    }
    case 2: {
      // aliases of aliases: ten levels of ten copies, 10^10 values if expanded
      std::string laughs = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
      for (int i = 1; i < 10; ++i) {
        const std::string prev = "*a" + std::to_string(i - 1);
        laughs += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
        for (int j = 0; j < 10; ++j) laughs += (j ? ", " : "") + prev;
        laughs += "]\n";
      }
      return {laughs + text, "ten levels of ten aliases before the file (10^10 values expanded)"};
    }
    default: {
      const auto lines = split_lines(text);
      const auto keys = key_lines(lines);
      if (keys.empty()) return kNothing;
      const KeyLine k = keys[r.below(keys.size())];
      std::string entries;
      for (int i = 0; i < 20000; ++i) entries += std::string(k.col + 2, ' ') + "- {name: n" + std::to_string(i) + "}\n";
      std::vector<std::string> out(lines.begin(), lines.begin() + k.line);
      out.push_back(lines[k.line].substr(0, k.col) + k.key + ":");
      std::string joined = join_lines(out) + entries;
      const size_t e = block_end(lines, k);
      for (size_t i = e; i < lines.size(); ++i) joined += lines[i] + "\n";
      return {joined, "'" + k.key + "' (line " + std::to_string(k.line + 1) + ") = a list of 20000 mappings"};
    }
  }
}

Result missing_file(const std::string& text, SplitMix& r) {
  const size_t mesh = text.find("file: ");
  if (mesh != std::string::npos && r.below(2) == 0) {
    const size_t e = text.find('\n', mesh);
    return {replaced(text, {mesh + 6, e - mesh - 6}, "meshes/no-such-mesh.stl"), "mesh file that is not there"};
  }
  const size_t prog = text.find("program: fw-central");
  if (prog != std::string::npos && r.below(2) == 0)
    return {replaced(text, {prog + 9, 10}, "./no-such-program"), "central program that is not there"};
  if (text.find("\nchain:") != std::string::npos || text.rfind("chain:", 0) == 0)
    return {text + "module_types: {ghost: modules/no-such-module.yaml}\n", "module type file that is not there"};
  // a module definition: the scene that uses it refers to a file never written
  return {text, "module definition file that is not there", true};
}

}  // namespace

const char* mutation_name(MutationKind kind) {
  static const char* const kNames[] = {"delete key",    "duplicate key", "change type", "extreme number",
                                       "bad bytes",     "truncate",      "swap values", "wrong nesting",
                                       "huge list",     "missing file"};
  return kNames[static_cast<int>(kind)];
}

Mutation mutate(const std::string& text, MutationKind kind, uint64_t seed) {
  SplitMix r(seed);
  Result m;
  switch (kind) {
    case MutationKind::DeleteKey: m = delete_key(text, r); break;
    case MutationKind::DuplicateKey: m = duplicate_key(text, r); break;
    case MutationKind::ChangeType: m = change_type(text, r); break;
    case MutationKind::ExtremeNumber: m = extreme_number(text, r); break;
    case MutationKind::BadBytes: m = bad_bytes(text, r); break;
    case MutationKind::Truncate: m = truncate(text, r); break;
    case MutationKind::SwapValues: m = swap_values(text, r); break;
    case MutationKind::WrongNesting: m = wrong_nesting(text, r); break;
    case MutationKind::HugeList: m = huge_list(text, r); break;
    case MutationKind::MissingFile: m = missing_file(text, r); break;
  }
  if (none(m)) {
    m = truncate(text, r);
    m.what = std::string(mutation_name(kind)) + " found nothing to change; " + m.what;
  }
  return m;
}

}  // namespace scenario

// --- CSV records -------------------------------------------------------------

namespace scenario {
namespace {

struct Csv {
  std::vector<std::string> comments;             // '#' lines, before the header
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> out;
  size_t b = 0;
  for (;;) {
    const size_t e = line.find(',', b);
    out.push_back(line.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) return out;
    b = e + 1;
  }
}

std::string join_cells(const std::vector<std::string>& cells) {
  std::string out;
  for (size_t i = 0; i < cells.size(); ++i) out += (i ? "," : "") + cells[i];
  return out;
}

Csv parse_csv(const std::string& text) {
  Csv c;
  bool header = false;
  for (const std::string& l : split_lines(text)) {
    if (!header && (l.empty() || l[0] == '#')) {
      c.comments.push_back(l);
    } else if (!header) {
      c.header = split_cells(l);
      header = true;
    } else if (!l.empty()) {
      c.rows.push_back(split_cells(l));
    }
  }
  return c;
}

std::string write_csv(const Csv& c) {
  std::vector<std::string> lines = c.comments;
  lines.push_back(join_cells(c.header));
  for (const auto& r : c.rows) lines.push_back(join_cells(r));
  return join_lines(lines);
}

std::string pick_of(SplitMix& r, const std::vector<std::string>& choices) { return choices[r.below(choices.size())]; }

}  // namespace

const char* csv_mutation_name(CsvMutationKind kind) {
  static const char* const kNames[] = {"truncate",   "bad bytes",  "extreme number", "text cell", "drop column",
                                       "dup column", "ragged row", "row order",      "oversize",  "empty"};
  return kNames[static_cast<int>(kind)];
}

Mutation mutate_csv(const std::string& text, CsvMutationKind kind, uint64_t seed) {
  SplitMix r(seed);
  Csv c = parse_csv(text);
  Mutation m;
  const size_t n_rows = c.rows.size(), n_cols = c.header.size();
  if (n_rows < 2 || n_cols < 2) return {text.substr(0, text.size() / 2), "a record too small to mutate: cut"};
  const size_t row = r.below(n_rows), col = r.below(n_cols);
  std::string& cell = c.rows[row][std::min(col, c.rows[row].size() - 1)];
  const std::string where = "row " + std::to_string(row + 1) + ", column " + std::to_string(col + 1);
  switch (kind) {
    case CsvMutationKind::Truncate: {
      const size_t at = r.below(text.size());
      return {text.substr(0, at), "cut at byte " + std::to_string(at)};
    }
    case CsvMutationKind::BadBytes: {
      const std::string bad = pick_of(r, {std::string("\xff"), std::string("\xc3"), std::string(1, '\0'), "\x1b[2J", "\r", "\t"});
      cell.insert(r.below(cell.size() + 1), bad);
      m.what = "a bad byte in " + where;
      break;
    }
    case CsvMutationKind::ExtremeNumber:
      cell = pick_of(r, {"nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "123456789012345678901234567890", "1e309"});
      m.what = where + " = " + cell;
      break;
    case CsvMutationKind::TextCell:
      cell = pick_of(r, {"abc", "1,5", "0x10", "1e", "\"1\"", " ", "--1", "1.2.3"});
      m.what = where + " = '" + cell + "'";
      break;
    case CsvMutationKind::DropColumn:
      if (r.below(2)) {
        c.header.erase(c.header.begin() + static_cast<long>(col));
        m.what = "column " + std::to_string(col + 1) + " dropped from the header only";
      } else {
        c.header.erase(c.header.begin() + static_cast<long>(col));
        for (auto& rw : c.rows)
          if (col < rw.size()) rw.erase(rw.begin() + static_cast<long>(col));
        m.what = "column " + std::to_string(col + 1) + " dropped";
      }
      break;
    case CsvMutationKind::DuplicateColumn: {
      const size_t other = (col + 1 + r.below(n_cols - 1)) % n_cols;
      c.header.push_back(c.header[col]);
      for (auto& rw : c.rows) rw.push_back(rw[std::min(other, rw.size() - 1)]);
      m.what = "header '" + c.header[col] + "' given twice";
      break;
    }
    case CsvMutationKind::RaggedRow:
      if (r.below(2) && c.rows[row].size() > 1) {
        c.rows[row].pop_back();
        m.what = "row " + std::to_string(row + 1) + " a cell short";
      } else {
        c.rows[row].push_back("1");
        m.what = "row " + std::to_string(row + 1) + " a cell more";
      }
      break;
    case CsvMutationKind::RowOrder: {
      const size_t other = (row + 1 + r.below(n_rows - 1)) % n_rows;
      if (r.below(2)) {
        std::swap(c.rows[row], c.rows[other]);
        m.what = "rows " + std::to_string(row + 1) + " and " + std::to_string(other + 1) + " swapped";
      } else {
        c.rows.insert(c.rows.begin() + static_cast<long>(row), c.rows[row]);
        m.what = "row " + std::to_string(row + 1) + " repeated";
      }
      break;
    }
    case CsvMutationKind::Oversize:
      switch (r.below(3)) {
        case 0: {
          // rows continuing the first column's step
          const std::vector<std::string> last = c.rows.back();
          for (size_t i = 0; c.rows.size() <= 200000; ++i) {
            std::vector<std::string> rw = last;
            rw[0] = std::to_string(std::strtod(last[0].c_str(), nullptr) + 0.001 * static_cast<double>(i + 1));
            c.rows.push_back(rw);
          }
          m.what = "200 001 rows";
          break;
        }
        case 1: {
          std::vector<std::string> rw = c.rows.back();
          rw[0] = "1000000";
          c.rows.push_back(rw);
          m.what = "a last row at 10^6";
          break;
        }
        default:
          cell = std::string(2u << 20, '7');
          m.what = where + " 2 MB long";
      }
      break;
    case CsvMutationKind::Empty:
      switch (r.below(3)) {
        case 0: return {"", "an empty file"};
        case 1: c.rows.clear(); m.what = "the header alone"; break;
        default: return {join_lines(c.comments) + "# nothing else\n", "comments alone"};
      }
      break;
  }
  m.text = write_csv(c);
  return m;
}

}  // namespace scenario
