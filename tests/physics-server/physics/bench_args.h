// Command-line numbers of the physics benchmarks (physics_bench,
// pipe_drive_bench): each argument must be a whole positive number of its
// kind, or the bench says which one it did not understand and stops, rather
// than run on a zero or a garbage value.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace chainsim::bench {

// the program's name: the usage up to its first space
inline int program_len(const char* usage) { return static_cast<int>(std::strcspn(usage, " ")); }

// "--help" / "-h" anywhere: the usage on stdout, exit 0
inline void help_or_continue(int argc, char** argv, const char* usage) {
  for (int a = 1; a < argc; ++a)
    if (!std::strcmp(argv[a], "--help") || !std::strcmp(argv[a], "-h")) {
      std::printf("usage: %s\n", usage);
      std::exit(0);
    }
}

// arg as a positive finite number (seconds), else the usage on stderr, exit 2
inline double positive(const char* arg, const char* what, const char* usage) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(arg, &end);
  if (end == arg || *end != '\0' || errno != 0 || !std::isfinite(v) || !(v > 0)) {
    std::fprintf(stderr, "%.*s: %s: not a positive number: '%s'\nusage: %s\n", program_len(usage), usage, what, arg,
                 usage);
    std::exit(2);
  }
  return v;
}

// arg as a positive whole number (iterations, modules), else as above
inline int positive_int(const char* arg, const char* what, const char* usage) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(arg, &end, 10);
  if (end == arg || *end != '\0' || errno != 0 || v <= 0 || v > 100000) {
    std::fprintf(stderr, "%.*s: %s: not a positive whole number: '%s'\nusage: %s\n", program_len(usage), usage, what,
                 arg, usage);
    std::exit(2);
  }
  return static_cast<int>(v);
}

}  // namespace chainsim::bench
