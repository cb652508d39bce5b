#pragma once

#include <cstdio>
#include <cstdlib>

/// Invariant checks: on in Debug and sanitizer builds, compiled out of Release.
/// Checks on emitted machine moves are not assertions: they reject in every build.
#if !defined(NDEBUG) || defined(MAXSLICE_ENABLE_ASSERTS)
#define MAXSLICE_ASSERT(cond)                                                                      \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            std::fprintf(stderr, "maxslice: internal check failed: %s (%s:%d)\n", #cond, __FILE__, \
                         __LINE__);                                                                \
            std::abort();                                                                          \
        }                                                                                          \
    } while (false)
#else
#define MAXSLICE_ASSERT(cond) ((void)0)
#endif
