// Socket directories: named after their server's pid, private, and those of
// servers that no longer exist removed (only those).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

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

}  // namespace
}  // namespace chainsim
