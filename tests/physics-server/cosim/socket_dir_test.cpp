// Socket directories: named after their server's pid, private, and those of
// servers that no longer exist removed (only those), of the old naming too.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cosim/socket_dir.h"
#include "temp_dir.h"

namespace chainsim {
namespace {

namespace fs = std::filesystem;

// the pid of a process that has ended and been reaped
pid_t dead_pid() {
  const pid_t p = fork();
  if (p == 0) _exit(0);
  waitpid(p, nullptr, 0);
  return p;
}

TEST(SocketDir, IsPrivateAndNamedAfterTheServer) {
  chainsim_test::TempDir t("chainsim-sockdir");
  const std::string d = make_socket_dir(t.path.string());
  const std::string name = fs::path(d).filename().string();
  EXPECT_EQ(name.rfind("chainsim-sock-" + std::to_string(getpid()) + "-", 0), 0u) << name;
  struct stat st;
  ASSERT_EQ(stat(d.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0700u);
}

TEST(SocketDir, OnlyThoseOfEndedServersAreRemoved) {
  chainsim_test::TempDir t("chainsim-sockdir");
  const fs::path stale = t.path / ("chainsim-sock-" + std::to_string(dead_pid()) + "-abcdef");
  const fs::path live = make_socket_dir(t.path.string());
  const fs::path other = t.path / "chainsim-sock-notapid-abcdef";
  const fs::path odd = t.path / ("chainsim-sock-" + std::to_string(dead_pid()) + "-toolong123");
  for (const auto& d : {stale, other, odd}) fs::create_directory(d);
  std::ofstream((stale / "chainsim.sock").string()) << "";
  // a symlink of a stale name pointing elsewhere is not followed
  const fs::path target = t.path / "keep";
  fs::create_directory(target);
  const fs::path link = t.path / ("chainsim-sock-" + std::to_string(dead_pid()) + "-linkkk");
  fs::create_directory_symlink(target, link);

  EXPECT_EQ(remove_stale_socket_dirs(t.path.string()), 1);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(odd));
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::exists(target));
}

// a Unix socket bound at path; listening (and returned open) if keep, else closed at once
int bound_socket(const fs::path& path, bool keep) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un sa{};
  sa.sun_family = AF_UNIX;
  std::snprintf(sa.sun_path, sizeof sa.sun_path, "%s", path.c_str());
  EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa), 0) << path;
  if (keep) {
    EXPECT_EQ(listen(fd, 1), 0);
    return fd;
  }
  close(fd);
  return -1;
}

// an old-naming directory chainsim-XXXXXX (mode 0700) holding a socket named chainsim.sock
fs::path old_dir(const fs::path& tmp, const std::string& letters, bool listening, int* fd) {
  const fs::path d = tmp / ("chainsim-" + letters);
  fs::create_directory(d);
  fs::permissions(d, fs::perms::owner_all, fs::perm_options::replace);
  *fd = bound_socket(d / "chainsim.sock", listening);
  return d;
}

void age(const fs::path& p, int seconds) {
  const auto t = fs::last_write_time(p) - std::chrono::seconds(seconds);
  for (const auto& de : fs::directory_iterator(p)) fs::last_write_time(de.path(), t);
  fs::last_write_time(p, t);
}

// the old naming says no pid: a directory goes only when nothing of this
// system has its socket bound, it holds nothing else, and it is not new
TEST(SocketDir, OldNamingIsRemovedOnlyWhenNoSocketIsBoundThere) {
  chainsim_test::TempDir t("chainsim-sockdir");
  int fd = -1, live_fd = -1;
  const fs::path stale = old_dir(t.path, "Ab12Cd", false, &fd);
  const fs::path live = old_dir(t.path, "Live01", true, &live_fd);  // a server of the old naming, running
  const fs::path fresh = old_dir(t.path, "Fresh1", false, &fd);
  const fs::path other = old_dir(t.path, "Other1", false, &fd);
  std::ofstream((other / "notes.txt").string()) << "not a socket directory";
  const fs::path empty = t.path / "chainsim-Empty1";
  fs::create_directory(empty);
  fs::permissions(empty, fs::perms::owner_all, fs::perm_options::replace);
  const fs::path open_mode = t.path / "chainsim-Mode77";
  fs::create_directory(open_mode);
  fs::permissions(open_mode, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec,
                  fs::perm_options::replace);
  const fs::path longer = t.path / "chainsim-test-Ab12Cd";
  fs::create_directory(longer);
  for (const auto& d : {stale, live, other, empty, open_mode, longer}) age(d, 600);

  EXPECT_EQ(remove_stale_old_socket_dirs(t.path.string(), 60), 2);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_FALSE(fs::exists(empty));
  EXPECT_TRUE(fs::exists(live / "chainsim.sock"));
  EXPECT_TRUE(fs::exists(fresh));
  EXPECT_TRUE(fs::exists(other / "notes.txt"));
  EXPECT_TRUE(fs::exists(open_mode));
  EXPECT_TRUE(fs::exists(longer));
  close(live_fd);
  // its server gone, the live one is stale too
  EXPECT_EQ(remove_stale_old_socket_dirs(t.path.string(), 60), 1);
  EXPECT_FALSE(fs::exists(live));
}

}  // namespace
}  // namespace chainsim
