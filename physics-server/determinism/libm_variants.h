// The same bytes on every x86-64 machine: glibc chooses at run time which
// variant of exp, expm1 (inside tanh), log, pow, sin, cos, atan, atan2 and
// others (tan, sincos, asin, acos, log2, log1p, the float functions) a
// process uses. On a CPU with FMA and AVX2 it takes their FMA variants, on one
// with FMA4 (AMD's older cores) FMA4 variants, else the baseline ones, and the
// variants differ in the last bit for up to about 1 argument in 1 000. A
// scene's trace then depends on the CPU it ran on.
//
// use_baseline_libm() makes this process and every process it starts use the
// baseline variants on every CPU: it adds glibc.cpu.hwcaps=-AVX2,-FMA4 to
// GLIBC_TUNABLES and starts the program again (execv of its own path, read
// from /proc/self/exe: the same pid, name and arguments), since glibc reads
// the tunable only when a process starts. A process that already has the
// tunable goes on at once, and the processes it starts (modules, workers)
// inherit it. glibc takes the FMA
// variants only where FMA and AVX2 are both usable, so hiding AVX2 hides
// them; FMA itself stays usable, so that glibc's fma() stays the hardware
// instruction (hiding FMA would make it a software emulation, several times
// slower, and the calibration's frame clock calls it). Without AVX2 glibc's
// memcpy and string functions take their AVX or SSE variants: the same
// results (docs/architecture.md, "Determinism").
//
// CHAINSIM_LIBM=machine in the environment keeps the machine's own variants
// (the bytes then hold only between CPUs that give glibc the same choice).
#pragma once

#include <string>

namespace chainsim {

// the hwcaps items that hide the FMA and FMA4 variants
inline constexpr const char* kBaselineLibmHwcaps = "-AVX2,-FMA4";

// GLIBC_TUNABLES as it must be for the baseline variants, from its current
// value (nullptr: unset): the items added to an existing glibc.cpu.hwcaps
// entry, or the entry appended; the same string when it already has them
std::string tunables_with_baseline_libm(const char* current);

// Call first in main(). Returns when the process already runs with the
// tunable (or CHAINSIM_LIBM=machine says not to; a process started by one
// that restarted inherits the tunable, which CHAINSIM_LIBM=machine set for
// it alone cannot undo); otherwise sets it and
// execs the program again, so it does not return. Where it cannot restart
// (set-user-ID, started through the dynamic loader, the exec failing, the
// tunable dropped at the restart) it says so on stderr, naming `program`,
// and returns: the run goes on with the machine's variants. Throws nothing.
void use_baseline_libm(const char* program, char** argv);

}  // namespace chainsim
