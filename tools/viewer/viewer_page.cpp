#include "viewer/viewer_page.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cosim/child_process.h"

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

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16 | static_cast<unsigned char>(in[i + 1]) << 8 |
                       static_cast<unsigned char>(in[i + 2]);
    out += k[v >> 18];
    out += k[(v >> 12) & 63];
    out += k[(v >> 6) & 63];
    out += k[v & 63];
  }
  if (i < in.size()) {
    const bool two = i + 1 < in.size();
    const unsigned v = static_cast<unsigned char>(in[i]) << 16 | (two ? static_cast<unsigned char>(in[i + 1]) << 8 : 0);
    out += k[v >> 18];
    out += k[(v >> 12) & 63];
    out += two ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return !p.empty() && fs::is_regular_file(p, ec);
}

// one mesh file (and, for .gltf, what it refers to) as the page wants it
nlohmann::json mesh_entry(const nlohmann::json& mesh, const nlohmann::json& scene, const std::string& run_dir,
                          std::vector<std::string>* warnings) {
  const std::string file = mesh.value("file", std::string());
  const std::string given = mesh.value("file_as_given", file);
  std::vector<fs::path> tries = {file};
  if (!given.empty() && fs::path(given).is_relative()) {
    const std::string source = scene.value("source", std::string());
    if (!source.empty()) tries.push_back(fs::path(source).parent_path() / given);
    tries.push_back(fs::path(run_dir) / given);
  }
  for (const fs::path& p : tries) {
    if (!is_file(p)) continue;
    const std::string bytes = read_text(p);
    nlohmann::json e = {{"base64", base64(bytes)}, {"bytes", bytes.size()}};
    std::string ext = p.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".gltf") {
      nlohmann::json extra = nlohmann::json::object();
      try {
        const nlohmann::json g = nlohmann::json::parse(bytes);
        for (const char* key : {"buffers", "images"})
          for (const auto& b : g.value(key, nlohmann::json::array())) {
            const std::string uri = b.value("uri", std::string());
            if (uri.empty() || uri.rfind("data:", 0) == 0) continue;
            const fs::path q = p.parent_path() / uri;
            if (is_file(q)) extra[uri] = base64(read_text(q));
            else if (warnings) warnings->push_back("the mesh " + p.string() + " refers to " + q.string() + ", which is not there");
          }
      } catch (const nlohmann::json::exception&) {
        // not JSON: the page's loader says what is wrong with it
      }
      e["extra"] = extra;
    }
    return e;
  }
  const std::string err = "the mesh file " + given + " is not there (looked for " + [&] {
    std::string s;
    for (const fs::path& p : tries) s += (s.empty() ? "" : ", ") + p.string();
    return s;
  }() + ")";
  if (warnings) warnings->push_back(err + ": the page is written without it");
  return {{"error", err}};
}

void collect_meshes(const nlohmann::json& env, const nlohmann::json& scene, const std::string& run_dir,
                    std::vector<std::string>* warnings, nlohmann::json* out) {
  if (!env.is_object()) return;
  const std::string type = env.value("type", std::string());
  if (type == "mesh" && env.contains("mesh") && env["mesh"].is_object()) {
    const std::string file = env["mesh"].value("file", std::string());
    if (!out->contains(file)) (*out)[file] = mesh_entry(env["mesh"], scene, run_dir, warnings);
  } else if (type == "group") {
    for (const auto& p : env.value("parts", nlohmann::json::array())) collect_meshes(p, scene, run_dir, warnings, out);
  }
}

}  // namespace

nlohmann::json environment_files(const nlohmann::json& scene, const std::string& run_dir,
                                 std::vector<std::string>* warnings) {
  nlohmann::json out = nlohmann::json::object();
  if (scene.is_object() && scene.contains("environment"))
    collect_meshes(scene["environment"], scene, run_dir, warnings, &out);
  return out;
}

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

// modules/NN-TYPE.log of every endpoint as {endpoint, type, text}, in endpoint order
nlohmann::json module_logs(const fs::path& dir) {
  std::vector<std::pair<int, fs::path>> files;
  std::error_code ec;
  for (const auto& de : fs::directory_iterator(dir / "modules", ec)) {
    const std::string name = de.path().filename().string();
    const size_t dash = name.find('-');
    if (de.path().extension() != ".log" || dash == 0 || dash == std::string::npos ||
        name.find_first_not_of("0123456789") != dash)
      continue;
    files.emplace_back(std::atoi(name.substr(0, dash).c_str()), de.path());
  }
  std::sort(files.begin(), files.end());
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [endpoint, path] : files) {
    const std::string stem = path.stem().string();
    out.push_back({{"endpoint", endpoint}, {"type", stem.substr(stem.find('-') + 1)}, {"text", read_text(path, false)}});
  }
  return out;
}

nlohmann::json replay_boot(const std::string& run_dir, std::vector<std::string>* warnings) {
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
  boot["logs"] = module_logs(d);
  boot["mesh_files"] = environment_files(boot["scene"], run_dir, warnings);
  return boot;
}

}  // namespace chainsim
