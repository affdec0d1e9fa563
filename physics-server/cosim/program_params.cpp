// Programs' parameter listings. See program_params.h.
#include "cosim/program_params.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "chainsim_protocol.h"
#include "cosim/child_process.h"
#include "model/pic_board.h"
#include "readers/safe_text.h"

namespace chainsim {
namespace {

constexpr int kListingTimeoutMs = 10000;  // wall clock: the program only prints a table
constexpr size_t kListingMaxBytes = 1 << 20;

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> out;
  size_t b = 0;
  for (;;) {
    const size_t e = line.find('\t', b);
    out.push_back(line.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) return out;
    b = e + 1;
  }
}

bool to_int32(const std::string& s, int32_t* v) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(s.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || x < INT32_MIN || x > INT32_MAX) return false;
  *v = static_cast<int32_t>(x);
  return true;
}

// the first lines of a program's output, for a message
std::string head_of(const std::string& text) {
  std::string t = text.substr(0, 300);
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  for (char& c : t)
    if (c == '\n') c = ' ';
  return t.empty() ? "nothing" : "\"" + shown_text(t) + "\"";
}

}  // namespace

ProgramParams parse_params_listing(const std::string& text, const std::string& program) {
  ProgramParams out;
  out.program = program;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != CS_PARAMS_HEADER)
    throw std::runtime_error("it printed " + head_of(text) + " instead of the line \"" CS_PARAMS_HEADER "\"");
  for (int n = 2; std::getline(in, line); ++n) {
    const std::vector<std::string> f = split_tabs(line);
    ParamDecl d;
    if (f.size() != 6 || f[0].empty() || !to_int32(f[2], &d.min) || !to_int32(f[3], &d.max) ||
        !to_int32(f[4], &d.def) || d.min > d.max || d.def < d.min || d.def > d.max)
      throw std::runtime_error("line " + std::to_string(n) + " of its listing is not name, type, min, max, "
                               "default and meaning separated by tabs: " + head_of(line));
    d.name = f[0];
    d.type = f[1];
    d.meaning = f[5];
    if (out.find(d.name)) throw std::runtime_error("it declares '" + shown_text(d.name) + "' twice");
    out.params.push_back(d);
  }
  return out;
}

ProgramParams read_program_params(const std::string& path, const std::string& program,
                                  const std::vector<std::string>& args) {
  if (access(path.c_str(), X_OK) != 0) throw std::runtime_error(path + " is not an executable file");
  // the listing goes to a temporary file without a name (unlinked at once),
  // so that nothing is left behind however this process ends, SIGKILL
  // included; closed on every way out, a failed spawn's exception included
  char tmpl[] = "/tmp/chainsim-params-XXXXXX";
  const int fd = mkostemp(tmpl, O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(std::string("cannot create a temporary file: ") + std::strerror(errno));
  unlink(tmpl);
  struct CloseAfter {
    int fd;
    ~CloseAfter() { close(fd); }
  } close_after{fd};
  std::string text;
  std::optional<ExitStatus> st;
  {
    ChildProcess child;
    ChildSpec spec;
    spec.program = path;
    spec.args = {CS_PARAMS_ARG};
    spec.args.insert(spec.args.end(), args.begin(), args.end());
    spec.stdout_fd = fd;
    child.spawn(spec);
    st = child.wait_for(kListingTimeoutMs);
    if (!st) child.terminate(200);
  }
  text.resize(kListingMaxBytes);
  size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = pread(fd, text.data() + got, text.size() - got, static_cast<off_t>(got));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::runtime_error(std::string("cannot read its listing: ") + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<size_t>(n);
  }
  text.resize(got);
  if (!st)
    throw std::runtime_error("it printed no listing within " + std::to_string(kListingTimeoutMs / 1000) +
                             " s (wall clock)");
  if (!st->exited || st->code != 0)
    throw std::runtime_error("it ended with " + st->text() + " and printed " + head_of(text));
  return parse_params_listing(text, program);
}

const ProgramParams& ProgramParamsCache::get(const std::string& path, const std::string& program,
                                             const std::function<void(const std::string& why)>& on_error,
                                             const std::vector<std::string>& args) {
  const std::string key = args.empty() ? path : path + " " + args.back();
  auto it = by_path_.find(key);
  if (it != by_path_.end()) return it->second;
  std::string why;
  try {
    return by_path_.emplace(key, read_program_params(path, program, args)).first->second;
  } catch (const std::exception& ex) {
    why = ex.what();
  }
  on_error(why);
  throw std::runtime_error(why);
}

void check_scene_programs(const Scene& scene, const std::string& firmware_dir) {
  const int n = static_cast<int>(scene.modules.size());
  // compiled at the first module on the PIC: its definition is checked against the board
  std::optional<ChainModel> chain;
  for (int i = 0; i <= n; ++i) {
    const SceneModule& e = i < n ? scene.modules[i] : scene.central;
    if (e.target == Target::Pic) {
      const std::string at = e.target_at.empty() ? e.firmware_at : e.target_at;
      if (pic_hex_path(e.firmware, firmware_dir).empty())
        throw SceneError(at + ": " + scene_endpoint_name(scene, i) + " runs on the PIC: " +
                         pic_hex_missing(e.firmware, firmware_dir));
      if (access(pic_module_program().c_str(), X_OK) != 0)
        throw SceneError(at + ": " + scene_endpoint_name(scene, i) + " runs on the PIC, but " + pic_module_program() +
                         " is missing: chainsim was built without libgpsim (install gpsim-dev and libglib2.0-dev, "
                         "then build again)");
      if (i < n) {
        if (!chain) chain = compile_chain(scene);
        const auto misfits = pic_board_misfits(chain->modules[static_cast<size_t>(i)]);
        if (!misfits.empty())
          throw SceneError(at + ": " + scene_endpoint_name(scene, i) + " runs on the PIC, and its module type does "
                           "not fit the board: " + misfits.front() +
                           (misfits.size() > 1 ? " (and " + std::to_string(misfits.size() - 1) + " more)" : ""));
      }
      continue;
    }
    const std::string path = program_path(e.firmware, firmware_dir);
    if (access(path.c_str(), X_OK) != 0)
      throw SceneError(e.firmware_at + ": program '" + e.firmware + "' of " + scene_endpoint_name(scene, i) +
                       " not found or not executable: " + path +
                       (e.firmware.find('/') == std::string::npos
                            ? " (a name is looked for in --firmware-dir, then next to chainsim)"
                            : ""));
  }
  ProgramParamsCache known;
  check_scene_params(scene, [&](const SceneModule& e, const std::string& who) -> const ProgramParams& {
    const bool pic = e.target == Target::Pic;
    const std::string hex = pic ? pic_hex_path(e.firmware, firmware_dir) : "";
    const std::string path = pic ? pic_module_program() : program_path(e.firmware, firmware_dir);
    return known.get(
        path, e.firmware,
        [&](const std::string& why) {
          const std::string first = e.param_at.empty() ? e.firmware_at : e.param_at.begin()->second;
          throw SceneError(first + ": " + who + " is given parameters, but " +
                           (pic ? "the parameter table of " + hex + " could not be read: " + why
                                : "its program " + path + " did not list the ones it declares when run with "
                                  CS_PARAMS_ARG ": " + why + " (a program linked with chainsim's hal-sim lists them)"));
        },
        pic ? std::vector<std::string>{hex} : std::vector<std::string>{});
  });
}

}  // namespace chainsim
