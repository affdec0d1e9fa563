#include "viewer_page.h"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "child_process.h"

namespace chainsim {

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p, bool required = true) {
  std::ifstream f(p, std::ios::binary);
  if (!f) {
    if (required) throw ViewerError("cannot read " + p.string());
    return {};
  }
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// text inside <script> or <style> must not close it early: "</script" in a JS
// string or regex becomes "<\/script", which means the same there
std::string escape_end_tag(const std::string& s, const std::string& tag) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (s[i] != '<' || i + 1 + tag.size() >= s.size() || s[i + 1] != '/') continue;
    bool match = true;
    for (size_t k = 0; k < tag.size() && match; ++k)
      match = std::tolower(static_cast<unsigned char>(s[i + 2 + k])) == tag[k];
    if (match) out += '\\';
  }
  return out;
}

// JSON inside <script type="application/json">: every '<' (only ever inside
// strings) as \u003c, so nothing can end or comment out the element
std::string script_json(const nlohmann::json& j) {
  const std::string s = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(s.size() + 64);
  for (char c : s) {
    if (c == '<') out += "\\u003c";
    else out += c;
  }
  return out;
}

std::string html_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

}  // namespace

std::string viewer_assets_dir() {
  if (const char* d = std::getenv("CHAINSIM_VIEWER_DIR"); d && *d) return d;
  return (fs::path(executable_dir()) / ".." / "share" / "chainsim").lexically_normal().string();
}

std::string viewer_page(const nlohmann::json& boot, const std::string& title) {
  const fs::path dir = viewer_assets_dir();
  if (!fs::exists(dir / "viewer.js") || !fs::exists(dir / "viewer.css"))
    throw ViewerError("the viewer bundle is not at " + dir.string() +
                      " (viewer.js, viewer.css): build it with `cmake --build build --target "
                      "chainsim_viewer_bundle` (needs node and npm: tools/setup.sh installs them)");
  const std::string js = escape_end_tag(read_text(dir / "viewer.js"), "script");
  const std::string css = escape_end_tag(read_text(dir / "viewer.css"), "style");
  std::string page;
  page.reserve(js.size() + css.size() + 4096);
  page += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
          "<link rel=\"icon\" href=\"data:,\">\n<title>";
  page += html_text(title);
  page += "</title>\n<style>\n" + css + "\n</style>\n</head>\n<body>\n";
  page += "<script type=\"application/json\" id=\"chainsim-data\">" + script_json(boot) + "</script>\n";
  page += "<script>\n" + js + "\n</script>\n</body>\n</html>\n";
  return page;
}

nlohmann::json replay_boot(const std::string& run_dir) {
  const fs::path d = run_dir;
  for (const char* f : {"scene.json", "trace.csv"})
    if (!fs::exists(d / f))
      throw ViewerError(run_dir + " is not a run directory: it has no " + f +
                        " (write one with `chainsim run --out DIR`)");
  nlohmann::json boot = {{"mode", "replay"}};
  try {
    boot["scene"] = nlohmann::json::parse(read_text(d / "scene.json"));
    const std::string summary = read_text(d / "summary.json", false);
    boot["summary"] = summary.empty() ? nlohmann::json(nullptr) : nlohmann::json::parse(summary);
  } catch (const nlohmann::json::exception& e) {
    throw ViewerError(run_dir + ": " + e.what());
  }
  boot["trace"] = read_text(d / "trace.csv");
  boot["bus"] = read_text(d / "bus.log", false);
  return boot;
}

}  // namespace chainsim
