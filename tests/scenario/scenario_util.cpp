#include "scenario_util.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <openssl/evp.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace scenario {
namespace {

// the directories a test made: removed when every test of the process passed,
// kept for a look when one failed
std::vector<std::string>& made_dirs() {
  static std::vector<std::string> dirs;
  return dirs;
}

class RemoveDirsOnSuccess : public ::testing::Environment {
 public:
  void TearDown() override {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ec;
    for (const auto& d : made_dirs()) std::filesystem::remove_all(d, ec);
  }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new RemoveDirsOnSuccess);

}  // namespace

std::string temp_dir(const std::string& tag) {
  std::string t = "/tmp/chainsim-test-" + tag + "-XXXXXX";
  if (!mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed");
  made_dirs().push_back(t);
  return t;
}

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string p = dir + "/" + name;
  std::ofstream(p) << text;
  return p;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

pid_t start_chainsim(const std::vector<std::string>& args, const std::string& err_path) {
  std::vector<std::string> all{CHAINSIM_EXE};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

std::pair<std::string, int> chainsim_stdout(const std::string& args) {
  FILE* p = popen((std::string(CHAINSIM_EXE) + " " + args + " 2>&1").c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int st = pclose(p);
  return {out, WIFEXITED(st) ? WEXITSTATUS(st) : -1};
}

Outcome wait_chainsim(pid_t pid, const std::string& out_dir, const std::string& err_path, double timeout_s) {
  Outcome o;
  int st = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (waitpid(pid, &st, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (WIFEXITED(st)) o.exit_code = WEXITSTATUS(st);
  if (WIFSIGNALED(st)) o.signal = WTERMSIG(st);
  o.stderr_text = read_file(err_path);
  o.dir = out_dir;
  std::ifstream in(out_dir + "/summary.json");
  if (in) o.summary = nlohmann::json::parse(in, nullptr, false);
  return o;
}

Outcome run(const std::vector<std::string>& args, const std::string& dir) {
  std::vector<std::string> a{"run"};
  a.insert(a.end(), args.begin(), args.end());
  a.push_back("--out");
  a.push_back(dir + "/run");
  const std::string err = dir + "/stderr.txt";
  return wait_chainsim(start_chainsim(a, err), dir + "/run", err);
}

std::vector<pid_t> children_of(pid_t parent) {
  std::vector<pid_t> kids;
  DIR* d = opendir("/proc");
  if (!d) return kids;
  while (dirent* e = readdir(d)) {
    const pid_t p = static_cast<pid_t>(std::atoi(e->d_name));
    if (p <= 0) continue;
    std::ifstream in("/proc/" + std::string(e->d_name) + "/stat");
    std::string stat;
    std::getline(in, stat);
    const auto close = stat.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 2));
    char state;
    int ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent && state != 'Z') kids.push_back(p);
  }
  closedir(d);
  return kids;
}

bool alive(pid_t pid) {
  if (kill(pid, 0) != 0) return false;
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  std::getline(in, stat);
  const auto close = stat.rfind(')');
  return close != std::string::npos && stat[close + 2] != 'Z';
}

bool wait_until(const std::function<bool()>& pred, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!pred()) {
    if (std::chrono::steady_clock::now() > deadline) return pred();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

std::string sha256_file(const std::string& path) {
  const std::string data = read_file(path);
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_Digest(data.data(), data.size(), md, &n, EVP_sha256(), nullptr);
  std::string hex;
  char b[3];
  for (unsigned i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%02x", md[i]);
    hex += b;
  }
  return hex;
}

std::map<std::string, std::vector<double>> read_trace(const std::string& path) {
  std::istringstream in(read_file(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream h(line);
  for (std::string c; std::getline(h, c, ',');) names.push_back(c);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream r(line);
    size_t i = 0;
    for (std::string v; std::getline(r, v, ',') && i < names.size(); ++i) cols[names[i]].push_back(std::stod(v));
  }
  return cols;
}

std::string scene_path(const std::string& name) {
  std::string here = __FILE__;
  return here.substr(0, here.rfind("/tests/scenario/")) + "/scenes/" + name + ".yaml";
}

Outcome run_scene(const std::string& tag, const std::string& name, double duration_s,
                  const std::vector<std::pair<std::string, std::string>>& edits) {
  const std::string base = name.substr(name.rfind('/') + 1);  // a scene in a folder of scenes/
  const std::string dir = temp_dir(tag + "-" + base);
  std::string text = read_file(scene_path(name));
  for (const auto& e : edits) {
    const size_t at = text.find(e.first);
    EXPECT_NE(at, std::string::npos) << e.first;
    if (at != std::string::npos) text.replace(at, e.first.size(), e.second);
  }
  const std::string scene = write_file(dir, base + ".yaml", text);
  return run({scene, "--duration", std::to_string(duration_s), "-q"}, dir);
}

std::string central_log(const Outcome& o, int n) {
  return read_file(o.dir + "/modules/" + (n < 10 ? "0" : "") + std::to_string(n) + "-central.log");
}

std::vector<double> log_times(const std::string& log, const std::string& what) {
  std::vector<double> out;
  const std::string key = what + " at ms ";
  for (size_t p = log.find(key); p != std::string::npos; p = log.find(key, p + 1))
    out.push_back(std::atof(log.c_str() + p + key.size()) * 1e-3);
  return out;
}

EnvForChildren::EnvForChildren(const std::string& n, const char* value) : name(n) {
  if (const char* t = getenv(name.c_str())) had = true, old = t;
  value ? setenv(name.c_str(), value, 1) : unsetenv(name.c_str());
}

EnvForChildren::~EnvForChildren() { had ? setenv(name.c_str(), old.c_str(), 1) : unsetenv(name.c_str()); }

std::vector<std::string> socket_dirs_in(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& de : std::filesystem::directory_iterator(dir))
    if (de.path().filename().string().rfind("chainsim-sock-", 0) == 0) out.push_back(de.path().string());
  return out;
}

std::vector<pid_t> processes_with_env(const std::string& text) {
  std::vector<pid_t> found;
  DIR* d = opendir("/proc");
  if (!d) return found;
  while (dirent* e = readdir(d)) {
    const pid_t p = static_cast<pid_t>(std::atoi(e->d_name));
    if (p <= 0 || !alive(p)) continue;
    if (read_file("/proc/" + std::string(e->d_name) + "/environ").find(text) != std::string::npos) found.push_back(p);
  }
  closedir(d);
  return found;
}

}  // namespace scenario
