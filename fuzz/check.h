// FUZZ_CHECK(condition, message): an invariant of the code under test. When it fails, the target prints
// where and why and aborts, which libFuzzer reports as a crash and saves the input as a reproducer.
#pragma once

#include <cstdio>
#include <cstdlib>

#define FUZZ_CHECK(condition, message)                                                                  \
  do {                                                                                                 \
    if (!(condition)) {                                                                                \
      std::fprintf(stderr, "%s:%d: invariant failed: %s\n  %s\n", __FILE__, __LINE__, #condition, message); \
      std::abort();                                                                                    \
    }                                                                                                  \
  } while (false)
