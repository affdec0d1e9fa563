#include "determinism/libm_variants.h"

#include <gtest/gtest.h>

using chainsim::tunables_with_baseline_libm;

TEST(BaselineLibm, AnUnsetOrEmptyTunablesGetsTheHwcapsEntryAlone) {
  EXPECT_EQ(tunables_with_baseline_libm(nullptr), "glibc.cpu.hwcaps=-AVX2,-FMA4");
  EXPECT_EQ(tunables_with_baseline_libm(""), "glibc.cpu.hwcaps=-AVX2,-FMA4");
}

TEST(BaselineLibm, OtherTunablesAreKeptAndTheEntryAppended) {
  EXPECT_EQ(tunables_with_baseline_libm("glibc.malloc.check=3"), "glibc.malloc.check=3:glibc.cpu.hwcaps=-AVX2,-FMA4");
  EXPECT_EQ(tunables_with_baseline_libm("glibc.malloc.check=3:glibc.malloc.tcache_count=0"),
            "glibc.malloc.check=3:glibc.malloc.tcache_count=0:glibc.cpu.hwcaps=-AVX2,-FMA4");
}

TEST(BaselineLibm, AnExistingHwcapsEntryGainsOnlyTheItemsItLacks) {
  EXPECT_EQ(tunables_with_baseline_libm("glibc.cpu.hwcaps=-FMA"), "glibc.cpu.hwcaps=-FMA,-AVX2,-FMA4");
  EXPECT_EQ(tunables_with_baseline_libm("glibc.cpu.hwcaps=-FMA4,-AVX512F"), "glibc.cpu.hwcaps=-FMA4,-AVX512F,-AVX2");
  EXPECT_EQ(tunables_with_baseline_libm("glibc.malloc.check=3:glibc.cpu.hwcaps=-FMA:glibc.malloc.tcache_count=0"),
            "glibc.malloc.check=3:glibc.cpu.hwcaps=-FMA,-AVX2,-FMA4:glibc.malloc.tcache_count=0");
  // an empty value
  EXPECT_EQ(tunables_with_baseline_libm("glibc.cpu.hwcaps="), "glibc.cpu.hwcaps=-AVX2,-FMA4");
}

TEST(BaselineLibm, ItemsAreComparedWholeNotAsPrefixes) {
  // -AVX2 is not -AVX, -FMA4 not -FMA (neither hides the FMA variants alone)
  EXPECT_EQ(tunables_with_baseline_libm("glibc.cpu.hwcaps=-AVX,-FMA"), "glibc.cpu.hwcaps=-AVX,-FMA,-AVX2,-FMA4");
  EXPECT_EQ(tunables_with_baseline_libm("glibc.cpu.hwcaps=-AVX2X"), "glibc.cpu.hwcaps=-AVX2X,-AVX2,-FMA4");
}

TEST(BaselineLibm, AStringThatHasThemIsReturnedUnchanged) {
  // what the restarted process finds: use_baseline_libm goes on without a restart
  for (const char* t : {"glibc.cpu.hwcaps=-AVX2,-FMA4", "glibc.cpu.hwcaps=-FMA4,-FMA,-AVX2",
                        "glibc.malloc.check=3:glibc.cpu.hwcaps=-AVX2,-FMA4"})
    EXPECT_EQ(tunables_with_baseline_libm(t), t);
  EXPECT_EQ(tunables_with_baseline_libm(tunables_with_baseline_libm("glibc.cpu.hwcaps=-FMA").c_str()),
            "glibc.cpu.hwcaps=-FMA,-AVX2,-FMA4");
}

TEST(BaselineLibm, EmptyEntriesBetweenColonsAreDropped) {
  EXPECT_EQ(tunables_with_baseline_libm("glibc.malloc.check=3::"), "glibc.malloc.check=3:glibc.cpu.hwcaps=-AVX2,-FMA4");
}
