// A program's parameter listing (cosim/program_params.h): parsed from the
// text hal-sim prints, and read from real processes: a shipped program, one
// whose declarations are wrong, and programs that do not list any.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

#include "chainsim_protocol.h"
#include "cosim/child_process.h"
#include "cosim/program_params.h"
#include "temp_dir.h"

namespace chainsim {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ProgramParams, ListingParsesIntoDeclarationsInOrder) {
  const ProgramParams p = parse_params_listing(
      CS_PARAMS_HEADER "\ncontrol_ms\tuint16\t1\t1000\t10\tcontrol period, ms\n"
                       "elbow_dir_deg\tint16\t-1\t359\t-1\tway the elbow turns; -1 = none\n",
      "fw-x");
  ASSERT_EQ(p.params.size(), 2u);
  EXPECT_EQ(p.program, "fw-x");
  EXPECT_EQ(p.names(), "control_ms, elbow_dir_deg");
  const ParamDecl* d = p.find("elbow_dir_deg");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->type, "int16");
  EXPECT_EQ(d->min, -1);
  EXPECT_EQ(d->max, 359);
  EXPECT_EQ(d->def, -1);
  EXPECT_EQ(d->meaning, "way the elbow turns; -1 = none");
  EXPECT_EQ(parse_params_listing(CS_PARAMS_HEADER "\n", "fw-none").names(), "none");
}

TEST(ProgramParams, BadListingsAreRefusedNamingTheLine) {
  EXPECT_EQ(error_of([] { parse_params_listing("chainsim hal: CHAINSIM_SOCKET is not set\n", "p"); }),
            "it printed \"chainsim hal: CHAINSIM_SOCKET is not set\" instead of the line \"" CS_PARAMS_HEADER "\"");
  EXPECT_EQ(error_of([] { parse_params_listing("", "p"); }),
            "it printed nothing instead of the line \"" CS_PARAMS_HEADER "\"");
  EXPECT_NE(error_of([] { parse_params_listing(CS_PARAMS_HEADER "\na\tint16\t5\t1\t3\tmin above max\n", "p"); })
                .find("line 2 of its listing is not name, type, min, max, default and meaning"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_params_listing(CS_PARAMS_HEADER "\na\tint16\t0\t9\t3\n", "p"); }).find("line 2"),
            std::string::npos);
  EXPECT_EQ(error_of([] {
              parse_params_listing(CS_PARAMS_HEADER "\na\tint16\t0\t9\t3\tx\na\tint16\t0\t9\t3\ty\n", "p");
            }),
            "it declares 'a' twice");
}

// a shipped program run for real: what it declares, as docs/firmware.md lists it
TEST(ProgramParams, AShippedProgramListsItsDeclarations) {
  const ProgramParams p = read_program_params(FW_TOUCH, "fw-touch");
  EXPECT_EQ(p.names(), "control_ms, release_ms");
  const ParamDecl* d = p.find("release_ms");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->type, "uint16");
  EXPECT_EQ(d->min, 0);
  EXPECT_EQ(d->max, 60000);
  EXPECT_EQ(d->def, 50);
}

// hal-sim checks the table before it lists it: a default outside its range is the program's mistake
TEST(ProgramParams, WrongDeclarationsAreNamedByTheProgram) {
  const std::string e = error_of([] { read_program_params(FW_BAD_PARAMS, "fw-test-bad-params"); });
  EXPECT_EQ(e, "it ended with exit code 2 and printed \"chainsim hal: hal_param_table[1] (\"level\"): its default "
               "is outside its range\"");
}

TEST(ProgramParams, AProgramThatListsNothingIsNamedWithWhatItDid) {
  EXPECT_EQ(error_of([] { read_program_params("/bin/true", "true"); }),
            "it printed nothing instead of the line \"" CS_PARAMS_HEADER "\"");
  chainsim_test::TempDir dir;
  const std::string script = dir.file("fw-sleeps");
  std::ofstream(script) << "#!/bin/sh\necho started\nexit 4\n";
  ASSERT_EQ(chmod(script.c_str(), 0755), 0);
  EXPECT_EQ(error_of([&] { read_program_params(script, "fw-sleeps"); }),
            "it ended with exit code 4 and printed \"started\"");
  EXPECT_EQ(error_of([&] { read_program_params(dir.file("missing"), "missing"); }),
            dir.file("missing") + " is not an executable file");
}

// the program writes its listing into a file that has no name, so a server
// killed meanwhile (SIGKILL) leaves nothing in /tmp
TEST(ProgramParams, TheListingGoesToAFileWithoutAName) {
  chainsim_test::TempDir dir;
  const std::string script = dir.file("fw-where");
  std::ofstream(script) << "#!/bin/sh\nreadlink /proc/self/fd/1\nexit 3\n";
  ASSERT_EQ(chmod(script.c_str(), 0755), 0);
  const std::string e = error_of([&] { read_program_params(script, "fw-where"); });
  EXPECT_NE(e.find("it ended with exit code 3 and printed \"/tmp/chainsim-params-"), std::string::npos) << e;
  EXPECT_NE(e.find(" (deleted)\""), std::string::npos) << e;
}

TEST(ProgramParams, ANameIsLookedForInTheFirmwareDirsFirst) {
  chainsim_test::TempDir a, b;
  const std::string in_b = b.file("fw-x");
  std::ofstream(in_b) << "#!/bin/sh\n";
  ASSERT_EQ(chmod(in_b.c_str(), 0755), 0);
  EXPECT_EQ(program_path("fw-x", a.path.string() + ":" + b.path.string()), in_b);
  EXPECT_EQ(program_path("fw-x", a.path.string()), executable_dir() + "/fw-x");
  EXPECT_EQ(program_path("./fw-x", b.path.string()), "./fw-x");
}

}  // namespace
}  // namespace chainsim
