// What the command-line front end's commands share: exit codes and error reporting.
#pragma once

#include <cstdio>

#include "maxslice/core/files.hpp"
#include "maxslice/core/result.hpp"

namespace maxslice::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
inline constexpr int kExitBadInput = 2;
/// `maxslice verify`: the program was read but is unsafe to run or does not build the part
/// (docs/verifier.md).
inline constexpr int kExitRefused = 3;

/// The longest error line printed: a message that quotes a file's bytes is cut there.
inline constexpr std::size_t kMaxMessageChars = 1000;

/// Prints "maxslice: error: ..." on stderr, one line whatever the message holds (control
/// bytes escaped, cut at kMaxMessageChars); the exit code: 1 for an internal error, 2 for
/// everything the user can fix (bad input, refused programs).
inline int report_error(const core::Error& e) {
    std::fprintf(stderr, "maxslice: error: %s\n",
                 core::printable(e.describe(), kMaxMessageChars).c_str());
    return e.code == core::ErrorCode::kInternal ? kExitInternal : kExitBadInput;
}

}  // namespace maxslice::app
