#pragma once
// Small helpers the test processes share: a file's bytes, and a word quoted for /bin/sh.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace maxslice::test {

/// The argument in single quotes for /bin/sh (a quote inside becomes '\'').
inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// The whole file (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace maxslice::test
