// The files of a PIC build (tools/pic-module/pic_build.h): the gplink map's
// symbols and sections, and the C line above an instruction in SDCC's .asm.
#include <gtest/gtest.h>

#include <fstream>

#include "pic-module/pic_build.h"
#include "temp_dir.h"

using namespace chainsim::pic;

namespace {

// excerpts of a real map (tools/pic-build.sh's fw-rotation.map)
const char* kMap = R"(gplink-1.4.0 #1107 (Jan  1 2021)
Map File - Created 11-28-2026  17:03:39

                                 Section Info
                  Section       Type    Address   Location Size(Bytes)
                ---------  ---------  ---------  ---------  ---------
          S_crt0i___entry       code   0x000000    program   0x000004
     S_main__control_step       code   0x0003d6    program   0x00038a
        S_crt0i___startup       code   0x003fc2    program   0x00009e
    S_hal_time__next_tick       code   0x004bf2    program   0x000016
S_hal_time__hal_tick_wait       code   0x004c7a    program   0x00000a
            stack_section      udata   0x000700       data   0x000100

                              Program Memory Usage
                               Start         End
                           ---------   ---------
                            0x000000    0x000003

                              Symbols - Sorted by Name
                     Name    Address   Location    Storage File
                ---------  ---------  ---------  --------- ---------
               _00106_DS_   0x001aa6    program     static /x/fixed_sin.asm
                  __entry   0x000000    program     extern /x/crt0i.asm
               _next_tick   0x004bf2    program     static /x/hal_time.asm
           _hal_tick_wait   0x004c7a    program     extern /x/hal_time.asm
            _control_step   0x0003d6    program     extern /x/main.asm
                __startup   0x003fc2    program     extern /x/crt0i.asm
           entry_loop_dec   0x003fd0    program     static /x/crt0i.asm
                   _stack   0x000700       data     extern /x/stack.S
               _stack_end   0x0007ff       data     extern /x/stack.S
)";

}  // namespace

TEST(PicBuild, TheMapGivesSymbolsSectionsAndFunctions) {
  PicBuild b;
  parse_gplink_map(kMap, &b);
  EXPECT_EQ(b.code_at("_next_tick"), 0x4bf2);
  EXPECT_EQ(b.code_at("_hal_tick_wait"), 0x4c7a);
  EXPECT_EQ(b.code_at("_nothing"), -1);
  EXPECT_EQ(b.section_size.at(0x4bf2), 0x16u);
  EXPECT_EQ(b.data.at("_stack"), 0x700u);
  EXPECT_EQ(b.data.at("_stack_end"), 0x7ffu);
  EXPECT_EQ(b.function_at(0x3d6), "control_step");
  EXPECT_EQ(b.function_at(0x1aa6), "control_step") << "SDCC's local labels are no functions";
  EXPECT_EQ(b.function_at(0x4bfa), "next_tick");
  EXPECT_EQ(b.function_at(0x2), "__entry") << "the runtime's functions keep their names";
  EXPECT_EQ(b.function_at(0x3fd4), "__startup") << "a label inside a function is no function";
  EXPECT_EQ(b.asm_file_at(0x3d6), "/x/main.asm");
}

TEST(PicBuild, MissingFilesAreNamedWithHowToBuildThem) {
  chainsim_test::TempDir d;
  try {
    load_pic_build(d.file("fw-mine.hex"));
    FAIL();
  } catch (const BuildError& e) {
    EXPECT_NE(std::string(e.what()).find("fw-mine.hex not found: build the program for the PIC"), std::string::npos)
        << e.what();
  }
  std::ofstream(d.file("fw-mine.hex")) << ":00000001FF\n";
  std::ofstream(d.file("fw-mine.cod")) << "x";
  try {
    load_pic_build(d.file("fw-mine.hex"));
    FAIL();
  } catch (const BuildError& e) {
    EXPECT_NE(std::string(e.what()).find("fw-mine.map (the linker's map) cannot be read"), std::string::npos)
        << e.what();
  }
  std::ofstream(d.file("fw-mine.map")) << kMap;
  std::ofstream(d.file("fw-mine.pic.json")) << R"({"flash_bytes": 100, "flash_total": 32768, "ram_bytes": 700,
      "ram_total": 2048, "stack_bytes": 256, "servos": 2})";
  const PicBuild b = load_pic_build(d.file("fw-mine.hex"));
  EXPECT_EQ(b.servos, 2);
  EXPECT_EQ(b.ram_bytes, 700u);
  EXPECT_EQ(b.cod, d.file("fw-mine.cod"));
}

TEST(PicBuild, TheCLineAboveAnInstruction) {
  chainsim_test::TempDir d;
  std::ofstream(d.file("main.asm")) << "_control_step:\n"
                                       ";\t.line\t54; /src/firmware/rotation/main.c\tif (ca_pos == 0)\n"
                                       "\tMOVF\t_ca_pos, W, B\n"
                                       "\tBNZ\t_00111_DS_\n"
                                       ";\t.line\t55; /src/firmware/rotation/main.c\treturn (int16_t)(posture_cdeg / 2);\n"
                                       "\tMOVF\t_posture_cdeg, W, B\n";
  SourceLines s;
  SourceLines::Where w;
  ASSERT_TRUE(s.find(d.file("main.asm"), 6, &w));
  EXPECT_EQ(w.file, "/src/firmware/rotation/main.c");
  EXPECT_EQ(w.line, 55);
  EXPECT_EQ(w.text, "return (int16_t)(posture_cdeg / 2);");
  ASSERT_TRUE(s.find(d.file("main.asm"), 4, &w));
  EXPECT_EQ(w.line, 54);
  EXPECT_FALSE(s.find(d.file("main.asm"), 1, &w)) << "nothing above the first C line";
  EXPECT_FALSE(s.find(d.file("gone.asm"), 10, &w));
}
