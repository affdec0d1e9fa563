// `chainsim run --watch`: the folders of a scene's programs' sources, watched
// with inotify, and the builds that make the programs from them.
//
// A build folder is one of --firmware-dir's folders that holds a
// CMakeCache.txt (an out-of-tree project built against chainsim's package),
// or chainsim's own build folder when the scene runs programs next to
// chainsim. Its sources are the project's source folder (CMAKE_HOME_DIRECTORY
// of its cache), every folder below it but build folders and hidden ones; for
// chainsim's own tree, firmware/, hal/ and hal-sim/. The scene file is
// watched too: a change to it reruns without building.
#pragma once

#include <signal.h>

#include <string>
#include <vector>

namespace chainsim {

struct WatchedBuild {
  std::string build_dir;              // cmake --build this
  std::vector<std::string> targets;   // --target ...; empty: the project's default
  std::string source_dir;             // watched below
  std::vector<std::string> only;      // when not empty: only these folders of source_dir (chainsim's tree)
};

// the builds of the scene's programs: --firmware-dir's CMake build folders,
// then chainsim's own (exe_dir/..) when it is a build folder. Throws
// std::runtime_error naming a folder whose cache names no source folder.
std::vector<WatchedBuild> watched_builds(const std::string& firmware_dirs, const std::string& exe_dir);

// the command that builds b, as argv
std::vector<std::string> build_command(const WatchedBuild& b);

// SIGINT and SIGTERM: what ends `chainsim run --watch`
sigset_t stop_signal_set();

class SourceWatch {
 public:
  // watches every folder of the builds' sources and the scene file's folder
  // (for the scene file only); throws std::runtime_error when inotify cannot
  SourceWatch(const std::vector<WatchedBuild>& builds, const std::string& scene_file);
  ~SourceWatch();
  SourceWatch(const SourceWatch&) = delete;
  SourceWatch& operator=(const SourceWatch&) = delete;

  struct Change {
    bool any = false;          // something changed
    bool sources = false;      // a source (.c, .h, CMakeLists.txt, .cmake...): build before running
    std::string first;         // the first file that changed, for the message
    bool interrupted = false;  // SIGINT or SIGTERM came while waiting
  };
  // waits for a change and for the files to settle (no event for quiet_s),
  // or for SIGINT / SIGTERM (blocked and read while waiting)
  Change wait(double quiet_s = 0.3);

  size_t folders() const { return dirs_.size(); }
  // true when SIGINT or SIGTERM came since the last wait (while a build ran):
  // read without waiting, so that it is not delivered once unblocked
  bool take_signal();

 private:
  void add_tree(const std::string& dir, const std::vector<std::string>& only);
  int fd_ = -1;
  int sig_fd_ = -1;
  std::vector<std::string> dirs_;  // by watch descriptor order
  std::vector<int> wds_;
  std::string scene_dir_, scene_name_;
  bool scene_dir_is_source_ = false;
};

}  // namespace chainsim
