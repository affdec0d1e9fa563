#include "testing/test_file.h"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "readers/safe_text.h"
#include "readers/strict_yaml.h"
#include "scene/scene_yaml.h"

namespace chainsim {
namespace fs = std::filesystem;
namespace {

[[noreturn]] void raise_test_error(const std::string& message) { throw TestFileError(message); }

// a test file or its scene through the strict reader's bounds: a regular file
// of at most 16 MiB (no device, no FIFO)
std::string read_text(const std::string& path, const std::string& what) {
  return StrictYaml(path, raise_test_error).read_file(what);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  std::string l;
  while (std::getline(s, l)) out.push_back(l);
  return out;
}

// where character `offset` of a scalar's value is written in its line raw,
// the value starting at start (after the quote, if any): a double-quoted
// scalar's escapes (\\, \", \x41, \u00e9...) and a single-quoted one's ''
// are written longer than the bytes they stand for. npos when the scalar's
// line ends first (it goes on on the next one)
size_t written_column(const std::string& raw, size_t start, char quote, size_t offset) {
  size_t i = start, k = 0;
  while (k < offset) {
    if (i >= raw.size() || (quote && raw[i] == quote && !(quote == '\'' && i + 1 < raw.size() && raw[i + 1] == '\'')))
      return std::string::npos;
    if (quote == '"' && raw[i] == '\\' && i + 1 < raw.size()) {
      const char e = raw[i + 1];
      const size_t digits = e == 'x' ? 2 : e == 'u' ? 4 : e == 'U' ? 8 : 0;
      const unsigned long cp = digits ? std::strtoul(raw.substr(i + 2, digits).c_str(), nullptr, 16) : 0;
      i += 2 + digits;
      k += !digits ? 1 : cp < 0x80 ? 1 : cp < 0x800 ? 2 : cp < 0x10000 ? 3 : 4;  // its UTF-8 bytes
    } else {
      i += quote == '\'' && raw[i] == '\'' ? 2 : 1;
      ++k;
    }
  }
  return i;
}

// file:line:column of character `offset` of the expectation in scalar node n
std::string expectation_where(const SceneYaml& y, const YAML::Node& n, const std::vector<std::string>& lines,
                              const std::string& text, size_t offset) {
  const YAML::Mark m = n.Mark();
  if (m.line < 0 || m.line >= static_cast<int>(lines.size())) return y.where(n);
  const std::string& raw = lines[m.line];
  const char first = raw.size() > static_cast<size_t>(m.column) ? raw[m.column] : '\0';
  const char quote = first == '"' || first == '\'' ? first : '\0';
  const size_t start = static_cast<size_t>(m.column) + (quote ? 1 : 0);
  size_t col = written_column(raw, start, quote, offset);
  if (col == std::string::npos) {
    // over several lines: found in the first line by its text, if it is there
    col = start + offset;
    const std::string probe = text.substr(std::min(offset, text.size()), 8);
    if (!probe.empty()) {
      // escapes only lengthen the written text: the token is at or after start + offset
      const size_t guess = raw.find(probe, start + offset);
      if (guess != std::string::npos) col = guess;
    }
  }
  return y.file() + ":" + std::to_string(m.line + 1) + ":" + std::to_string(col + 1);
}

// leaves of the overrides map: nested maps are merged key by key
void flatten(const SceneYaml& y, const YAML::Node& map, std::vector<std::string> path, std::vector<SceneEdit>* out) {
  for (const auto& kv : map) {
    std::vector<std::string> p = path;
    p.push_back(kv.first.as<std::string>());
    if (kv.second.IsMap() && kv.second.size() > 0) flatten(y, kv.second, p, out);
    else out->push_back({p, kv.second, y.where(kv.first)});
  }
}

void load_params(const SceneYaml& y, const YAML::Node& params, std::vector<SceneEdit>* out) {
  for (const auto& kv : params) {
    const std::string who = kv.first.as<std::string>();
    std::vector<std::string> base;
    if (who == "central") base = {"central", "params"};
    else if (who == "modules") base = {"chain", "*", "params"};
    else if (who.size() >= 2 && who[0] == 'm' && who.find_first_not_of("0123456789", 1) == std::string::npos &&
             who.size() <= 3) base = {"chain", who.substr(1), "params"};
    else y.fail(kv.first, "unknown key '" + who + "' in 'params' (known: central, modules, m0, m1, ...)");
    if (!kv.second.IsMap()) y.fail(kv.second, "'params." + who + "' must be a mapping of name: integer");
    for (const auto& p : kv.second) {
      const std::string name = p.first.as<std::string>();
      if (name.empty() || name.size() > 15) y.fail(p.first, "parameter name '" + name + "' must have 1 to 15 characters");
      int64_t v = 0;
      try {
        v = p.second.as<int64_t>();
      } catch (const YAML::Exception&) {
        y.fail(p.second, "'params." + who + "." + name + "' must be an integer");
      }
      if (v < INT32_MIN || v > INT32_MAX) y.fail(p.second, "'params." + who + "." + name + "' is out of the 32-bit range");
      std::vector<std::string> path = base;
      path.push_back(name);
      out->push_back({path, p.second, y.where(p.first)});
    }
  }
}

// applies path[i..] of an edit below node; throws std::string
void apply_at(YAML::Node node, const std::vector<std::string>& path, size_t i, const YAML::Node& value) {
  const std::string& seg = path[i];
  if (seg == "chain" && i + 1 < path.size()) {
    YAML::Node chain = node["chain"];
    if (!chain) throw std::string("the scene has no 'chain'");
    if (chain.IsScalar()) {  // "RRH" -> [{type: rotation}, {type: rotation}, {type: helicoidal}]
      YAML::Node seq(YAML::NodeType::Sequence);
      for (char c : chain.as<std::string>()) {
        const std::string type = module_type_for_letter(c);
        if (type.empty()) throw std::string("the scene's chain has an unknown module letter '") + c + "'";
        YAML::Node m;
        m["type"] = type;
        seq.push_back(m);
      }
      node["chain"] = seq;
      chain = node["chain"];
    }
    if (!chain.IsSequence()) throw std::string("the scene's 'chain' is not a list of modules");
    const size_t n = chain.size();
    if (path[i + 1] == "*") {
      for (size_t k = 0; k < n; ++k) apply_at(chain[k], path, i + 2, value);
      return;
    }
    const std::string& index = path[i + 1];
    if (index.empty() || index.size() > 6 || index.find_first_not_of("0123456789") != std::string::npos)
      throw "'chain' is edited by module number (chain.0, chain.1, ...), not '" + shown_text_cut(index, 40) + "'";
    const size_t k = std::stoul(index);
    if (k >= n)
      throw "m" + path[i + 1] + ": the chain has " + std::to_string(n) + " modules (m0..m" + std::to_string(n - 1) + ")";
    if (!chain[k].IsMap()) throw "chain[" + path[i + 1] + "] is not a mapping";
    apply_at(chain[k], path, i + 2, value);
    return;
  }
  if (i + 1 == path.size()) {
    if (value.IsNull()) node.remove(seg);
    else node[seg] = YAML::Clone(value);
    return;
  }
  if (!node[seg] || !node[seg].IsMap()) node[seg] = YAML::Node(YAML::NodeType::Map);
  apply_at(node[seg], path, i + 1, value);
}

// "file:L:C: " at the start of a scene error names a place in the edited text,
// which is no file: drop it
std::string without_location(const std::string& msg, const std::string& file) {
  if (msg.rfind(file + ":", 0) != 0) return msg;
  size_t i = file.size() + 1;
  const size_t sp = msg.find(": ", i);
  if (sp == std::string::npos) return msg;
  if (msg.substr(i, sp - i).find_first_not_of("0123456789:") == std::string::npos) return msg.substr(sp + 2);
  return msg;
}

}  // namespace

std::vector<uint64_t> parse_seed_range(const std::string& text) {
  auto one = [&](const std::string& s) -> uint64_t {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 18)
      throw std::invalid_argument("'" + text + "': expected a seed or a range A..B of non-negative integers");
    return std::stoull(s);
  };
  const size_t dots = text.find("..");
  if (dots == std::string::npos) return {one(text)};
  const uint64_t a = one(text.substr(0, dots)), b = one(text.substr(dots + 2));
  if (b < a) throw std::invalid_argument("'" + text + "': the range A..B needs A <= B");
  if (b - a >= 10000) throw std::invalid_argument("'" + text + "': more than 10000 seeds");
  std::vector<uint64_t> out;
  for (uint64_t s = a; s <= b; ++s) out.push_back(s);
  return out;
}

TestFile load_test_text(const std::string& text, const std::string& name) {
  const SceneYaml y{name};
  TestFile t;
  t.file = name;
  try {
    // a syntax error, a second document or a key given twice is an error at its line and column
    const YAML::Node root = StrictYaml(name, raise_test_error).parse(text);
    if (!root || !root.IsMap()) throw TestFileError(name + ": a test file must be a YAML mapping");
    y.keys(root, "test",
           {"name", "description", "scene", "duration_s", "seed", "seeds", "overrides", "params", "on_module_fault",
            "expect"});
    if (!root["name"]) y.fail(root, "missing key 'name'");
    if (!root["scene"]) y.fail(root, "missing key 'scene' (the scene file, relative to this file)");
    if (!root["expect"]) y.fail(root, "missing key 'expect' (a list of expectations)");
    t.name = y.text(root, "name", "", "test");
    t.description = root["description"] ? y.text(root, "description", "", "test") : "";
    const std::string scene = y.text(root, "scene", "", "test");
    t.scene_where = y.where(root["scene"]);
    const fs::path sp(scene);
    t.scene_file = sp.is_absolute() ? scene : (fs::path(name).parent_path() / sp).lexically_normal().string();
    if (t.scene_file.empty()) t.scene_file = scene;

    if (const YAML::Node d = root["duration_s"]) {
      y.number(root, "duration_s", 0, 0.001, 86400.0, "test");
      t.edits.push_back({{"duration_s"}, d, y.where(d)});
    }
    if (root["seed"] && root["seeds"]) y.fail(root["seeds"], "give either 'seed' or 'seeds', not both");
    if (const YAML::Node s = root["seed"]) {
      t.seeds_where = y.where(s);
      try {
        t.seeds = parse_seed_range(s.as<std::string>());
      } catch (const std::exception&) {
        y.fail(s, "'test.seed' must be a non-negative integer");
      }
      if (t.seeds.size() != 1) y.fail(s, "'test.seed' is one seed; use 'seeds' for a range");
    } else if (const YAML::Node s = root["seeds"]) {
      t.seeds_where = y.where(s);
      if (s.IsSequence() && s.size() > 0) {
        for (const auto& e : s) {
          try {
            const auto one = parse_seed_range(e.as<std::string>());
            if (one.size() != 1) throw std::invalid_argument("");
            t.seeds.push_back(one[0]);
          } catch (const std::exception&) {
            y.fail(e, "each of 'test.seeds' must be a non-negative integer");
          }
        }
      } else if (s.IsScalar()) {
        try {
          t.seeds = parse_seed_range(s.as<std::string>());
        } catch (const std::invalid_argument& e) {
          y.fail(s, std::string("'test.seeds' ") + e.what());
        }
      } else {
        y.fail(s, "'test.seeds' must be a list of seeds or a range \"A..B\"");
      }
    }
    t.on_module_fault = y.choice(root, "on_module_fault", "stop", {"stop", "limp"}, "test");
    if (const YAML::Node o = root["overrides"]) {
      if (!o.IsMap()) y.fail(o, "'overrides' must be a mapping of scene keys");
      flatten(y, o, {}, &t.edits);
    }
    if (const YAML::Node p = root["params"]) {
      if (!p.IsMap()) y.fail(p, "'params' must be a mapping (central, modules, m0, m1, ...)");
      load_params(y, p, &t.edits);
    }

    const YAML::Node ex = root["expect"];
    if (!ex.IsSequence() || ex.size() == 0) y.fail(ex, "'expect' must be a non-empty list of expectations");
    const std::vector<std::string> lines = lines_of(text);
    for (const auto& n : ex) {
      if (!n.IsScalar()) y.fail(n, "an expectation must be one line of text, e.g. \"chain.distance_m >= 0.2\"");
      const std::string s = n.as<std::string>();
      try {
        t.expect.push_back({parse_expectation(s), expectation_where(y, n, lines, s, 0)});
      } catch (const ExpectationError& e) {
        throw TestFileError(expectation_where(y, n, lines, s, e.offset) + ": " + e.what() + " in \"" + s + "\"");
      }
    }
  } catch (const SceneError& e) {
    throw TestFileError(e.what());
  }
  return t;
}

TestFile load_test_file(const std::string& path) { return load_test_text(read_text(path, "test file"), path); }

Scene load_test_scene(const TestFile& test, std::optional<uint64_t> seed, const LoadedSceneCheck& check) {
  const std::string text = read_text(test.scene_file, "scene file (" + test.scene_where + ")");
  std::vector<SceneEdit> edits = test.edits;
  if (seed) edits.push_back({{"seed"}, YAML::Node(std::to_string(*seed)), test.seeds_where.empty() ? "--seeds" : test.seeds_where});

  YAML::Node base;
  try {
    base = YAML::Load(text);
  } catch (const YAML::Exception&) {
    base = YAML::Node();
  }
  // the scene with the first k edits
  auto edited = [&](size_t k) -> std::string {
    if (k == 0 || !base.IsMap()) return text;
    YAML::Node root = YAML::Clone(base);
    for (size_t i = 0; i < k; ++i) {
      try {
        apply_at(root, edits[i].path, 0, edits[i].value);
      } catch (const std::string& what) {
        throw TestFileError(edits[i].where + ": " + what);
      }
    }
    YAML::Emitter out;
    out << root;
    return out.c_str();
  };
  const auto load = [&](const std::string& scene_text) {
    Scene s = load_scene_text(scene_text, test.scene_file);
    if (check) check(s);
    return s;
  };
  try {
    return load(edited(edits.size()));
  } catch (const SceneError& all) {
    try {
      load(text);
    } catch (const SceneError& e) {
      throw TestFileError(test.scene_where + ": the scene does not load: " + e.what());
    }
    // the first edit that breaks the scene is the culprit
    for (size_t k = 1; k <= edits.size(); ++k) {
      try {
        load(edited(k));
      } catch (const SceneError& e) {
        throw TestFileError(edits[k - 1].where + ": " + without_location(e.what(), test.scene_file));
      }
    }
    throw TestFileError(test.scene_where + ": " + without_location(all.what(), test.scene_file));
  }
}

std::vector<std::string> find_test_files(const std::vector<std::string>& paths) {
  std::vector<std::string> out;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> found;
        // symbolic links are not followed into folders; one that loops or
      // dangles under a test file's name is an error naming it
      fs::recursive_directory_iterator it(p, ec), end;
      for (;; it.increment(ec)) {
        if (ec) throw TestFileError(p + ": cannot read this folder: " + ec.message());
        if (it == end) break;
        const std::string f = it->path().string();
        if (f.size() <= 10 || !f.ends_with(".test.yaml")) continue;
        std::error_code fe;
        if (it->is_regular_file(fe)) {
          found.push_back(f);
        } else if (fe) {
          throw TestFileError(f + ": cannot read this test file: " + fe.message());
        } else if (!it->is_directory(fe)) {
          throw TestFileError(f + ": not a regular file (a FIFO, device or socket)");
        }
      }
      std::sort(found.begin(), found.end());
      if (found.empty()) throw TestFileError(p + ": no *.test.yaml files in this folder");
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p, ec)) {
      out.push_back(p);
    } else {
      throw TestFileError(p + ": no such test file or folder");
    }
  }
  return out;
}

}  // namespace chainsim
