// Counts heap allocations in a test binary by interposing glibc's malloc
// family (libode's allocations go through them too). Include it in exactly one
// source file of a test binary; set g_counting around the code under test and
// read g_allocations. Without glibc, or under a sanitizer, CHAINSIM_COUNT_MALLOC
// stays undefined and the test should skip.
#pragma once

#include <cstddef>

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define CHAINSIM_COUNT_MALLOC 1
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
}
namespace {
thread_local bool g_counting = false;
thread_local long g_allocations = 0;
}  // namespace
extern "C" void* malloc(size_t n) {
  if (g_counting) ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void* calloc(size_t a, size_t b) {
  if (g_counting) ++g_allocations;
  return __libc_calloc(a, b);
}
extern "C" void* realloc(void* p, size_t n) {
  if (g_counting) ++g_allocations;
  return __libc_realloc(p, n);
}
#endif
