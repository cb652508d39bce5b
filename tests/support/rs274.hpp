// LinuxCNC's standalone G-code interpreter, rs274 (Debian package linuxcnc-uspace), run on a
// program the way the tests check our linuxcnc output against a real controller's reading.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace maxslice::test {

/// What one rs274 run left: its exit status (0 when it read the whole program), the canonical
/// calls it printed and what it wrote on stderr.
struct Rs274Run {
    int status = -1;
    std::string canon;
    std::string errors;
};

/// The interpreter's path ($MAXSLICE_RS274 first), or empty when it is not installed.
std::filesystem::path find_rs274();

/// Runs rs274 in batch mode (-g, stdin closed, at most 120 s) on `program`, in a folder of its
/// own that is also its HOME: rs274 truncates and maps $HOME/.tool.mmap, so two runs sharing a
/// HOME (ctest -j) crash each other with SIGBUS. Nothing when rs274 is not installed.
std::optional<Rs274Run> run_rs274(const std::string& program);

/// The axis values (x, y, z, a, b, c) of the canonical STRAIGHT_FEED calls, in order, and also of
/// the STRAIGHT_TRAVERSE calls when `traverses`. A call whose six values do not parse gives NaN.
std::vector<std::array<double, 6>> canonical_moves(const std::string& canon, bool traverses);

/// True when rs274's stderr holds nothing but its "executing" lines.
bool only_executing(const std::string& errors);

}  // namespace maxslice::test
