#pragma once
// Helpers shared by the io tests: test data paths and scratch files.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "maxslice/io/read_mesh.hpp"

namespace maxslice::io::test {

/// A file of the shared test data set (MANIFEST.md), by path relative to it.
inline std::filesystem::path testdata(std::string_view relative) {
    return std::filesystem::path(MAXSLICE_TESTDATA_DIR) / relative;
}

/// A file of this directory's own data.
inline std::filesystem::path local_data(std::string_view name) {
    return std::filesystem::path(MAXSLICE_IO_TEST_DATA_DIR) / name;
}

/// A scratch directory removed at the end of the test.
class ScratchDir {
public:
    ScratchDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = "maxslice_io_" + std::to_string(::getpid());
        if (info != nullptr)
            name += std::string("_") + info->test_suite_name() + "_" + info->name();
        for (char& c : name) {
            if (c == '/') c = '_';
        }
        dir_ = std::filesystem::temp_directory_path() / name;
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    /// Writes bytes to a file in the directory and returns its path.
    std::filesystem::path write(std::string_view name, std::string_view bytes) const {
        const std::filesystem::path p = dir_ / name;
        std::ofstream out(p, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return p;
    }
    [[nodiscard]] const std::filesystem::path& path() const { return dir_; }

private:
    std::filesystem::path dir_;
};

/// True when text contains part.
inline bool contains(std::string_view text, std::string_view part) {
    return text.find(part) != std::string_view::npos;
}

/// All warnings as one string, for failure messages.
inline std::string joined(const std::vector<std::string>& warnings) {
    std::string s;
    for (const std::string& w : warnings) s += "\n  " + w;
    return s.empty() ? "(none)" : s;
}

}  // namespace maxslice::io::test
