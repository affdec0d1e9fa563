// The run directory checked before a run: created when missing, refused with
// the path and the reason when it cannot be written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "output/run_dir.h"
#include "temp_dir.h"

namespace chainsim {
namespace {

namespace fs = std::filesystem;

TEST(RunDir, MissingDirectoryIsCreatedWithItsParents) {
  chainsim_test::TempDir t("chainsim-rundir");
  const std::string dir = t.file("a/b/run");
  const RunDirCheck r = prepare_run_dir(dir);
  EXPECT_EQ(r.error, "");
  EXPECT_FALSE(r.had_run);
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_TRUE(fs::is_empty(dir));  // the probe file is gone
}

TEST(RunDir, AFileIsNotARunDirectory) {
  chainsim_test::TempDir t("chainsim-rundir");
  std::ofstream(t.file("f")) << "x";
  EXPECT_EQ(prepare_run_dir(t.file("f")).error, "--out '" + t.file("f") + "': exists and is not a directory");
  EXPECT_NE(prepare_run_dir(t.file("f/run")).error.find("--out '" + t.file("f/run") + "': cannot create"),
            std::string::npos);
}

TEST(RunDir, AFullDeviceCannotHoldARun) {
  // /dev/full as a directory's parent: not a directory
  EXPECT_NE(prepare_run_dir("/dev/full/x").error.find("cannot create the directory"), std::string::npos);
}

TEST(RunDir, AnEarlierRunIsReported) {
  chainsim_test::TempDir t("chainsim-rundir");
  EXPECT_FALSE(prepare_run_dir(t.path.string()).had_run);
  std::ofstream(t.file("summary.json")) << "{}";
  EXPECT_TRUE(prepare_run_dir(t.path.string()).had_run);
}

}  // namespace
}  // namespace chainsim
