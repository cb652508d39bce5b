// Input checks and output files: nothing blocks on a special file, nothing a user had is lost.
#include "maxslice/core/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace maxslice::core {
namespace {

std::string errno_text(int err) {
    return std::strerror(err);
}

// "part file " for "part file", nothing for "".
std::string fmt_what(std::string_view what) {
    return what.empty() ? std::string() : std::string(what) + " ";
}

Error io_error(std::string message, const std::filesystem::path& path) {
    return Error{ErrorCode::kIo, std::move(message), printable(path.string())};
}

// Writes all of `bytes` to `fd`, retrying on EINTR and short writes; 0 or the errno.
int write_all(int fd, std::string_view bytes) {
    const char* p = bytes.data();
    std::size_t left = bytes.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    return 0;
}

// The file's identity, when it exists.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
    struct stat sa {
    }, sb{};
    if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0) {
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    }
    std::error_code ea, eb;
    const auto ca = std::filesystem::weakly_canonical(std::filesystem::absolute(a, ea), ea);
    const auto cb = std::filesystem::weakly_canonical(std::filesystem::absolute(b, eb), eb);
    return !ea && !eb && ca == cb;
}

}  // namespace

Result<void> check_input_file(const std::filesystem::path& path, std::string_view what) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        const int err = errno;
        return std::unexpected(
            io_error(fmt_what(what) + "cannot be read: " + errno_text(err), path));
    }
    if (S_ISREG(st.st_mode)) return {};
    const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                       : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a regular file";
    return std::unexpected(io_error(
        fmt_what(what) + "is " + kind + ", not a regular file: give the path of a file", path));
}

// Writes to what is not a file a user keeps (a pipe, a terminal, /dev/stdout, /dev/null):
// straight into it, every error checked.
Result<void> write_stream(const std::filesystem::path& path, std::string_view bytes,
                          bool truncate) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | (truncate ? O_TRUNC : 0));
    if (fd < 0) {
        const int err = errno;
        return std::unexpected(io_error("cannot open for writing: " + errno_text(err), path));
    }
    if (const int err = write_all(fd, bytes); err != 0) {
        ::close(fd);
        return std::unexpected(io_error("write failed: " + errno_text(err), path));
    }
    if (::close(fd) != 0) {
        const int err = errno;
        return std::unexpected(io_error("write failed (closing): " + errno_text(err), path));
    }
    return {};
}

Result<void> write_file_atomic(const std::filesystem::path& given, std::string_view bytes,
                               Durability durability) {
    if (given.empty()) {
        return fail(ErrorCode::kInvalidInput, "the output path is empty: name a file");
    }
    if (given == "-") return write_stdout(bytes);
    struct stat st {};
    const bool exists = ::stat(given.c_str(), &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) {
        return std::unexpected(io_error("the output is a directory, not a file", given));
    }
    const std::string text = given.lexically_normal().string();
    if (exists &&
        (!S_ISREG(st.st_mode) || text.starts_with("/dev/") || text.starts_with("/proc/"))) {
        return write_stream(given, bytes, S_ISREG(st.st_mode));
    }
    if (!given.has_filename() || given.filename() == "." || given.filename() == "..") {
        return std::unexpected(io_error("the output path names a folder, not a file", given));
    }
    // A link is followed: the file it names is replaced, the link stays.
    std::filesystem::path path = given;
    if (exists) {
        std::error_code ec;
        auto real = std::filesystem::canonical(given, ec);
        if (!ec) path = std::move(real);
    }
    // The temporary file lives beside the target, so the rename stays on one file system; it
    // is created as an ordinary new file would be (mode 0666 less the umask), and a file
    // replaced keeps its own mode.
    static std::atomic<unsigned> counter{0};
    std::string tmp;
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        tmp = path.string() + "." + std::to_string(::getpid()) + "." +
              std::to_string(counter.fetch_add(1)) + ".tmp";
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    if (fd < 0) {
        const int err = errno;
        return std::unexpected(io_error(
            "cannot create a file beside the output: " + errno_text(err) + "; nothing written",
            given));
    }
    const auto give_up = [&](const char* step, int err) {
        ::unlink(tmp.c_str());
        return std::unexpected(io_error(std::string(step) + ": " + errno_text(err) +
                                            "; the previous file (if any) is unchanged",
                                        given));
    };
    if (const int err = write_all(fd, bytes); err != 0) {
        ::close(fd);
        return give_up("write failed", err);
    }
    if (exists && ::fchmod(fd, st.st_mode & 07777) != 0) {
        const int err = errno;
        ::close(fd);
        return give_up("cannot set the file's permissions", err);
    }
    if (durability == Durability::kSynced && ::fsync(fd) != 0) {
        const int err = errno;
        ::close(fd);
        return give_up("write failed (flushing to disk)", err);
    }
    if (::close(fd) != 0) return give_up("write failed (closing)", errno);
    if (::rename(tmp.c_str(), path.c_str()) != 0) return give_up("cannot replace the file", errno);
    return {};
}

Result<void> write_stdout(std::string_view bytes) {
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), stdout) == bytes.size();
    const int err = errno;
    if (!ok || std::fflush(stdout) != 0) {
        return fail(ErrorCode::kIo, "write failed: " + errno_text(ok ? errno : err),
                    "standard output");
    }
    return {};
}

Result<void> check_output_not_input(const std::filesystem::path& output, std::string_view option,
                                    const std::vector<std::filesystem::path>& inputs) {
    for (const auto& in : inputs) {
        if (in.empty()) continue;
        if (same_file(output, in)) {
            return fail(ErrorCode::kInvalidInput,
                        "the output would overwrite the input " + printable(in.string()) +
                            ": name another file",
                        std::string(option) + " " + printable(output.string()));
        }
    }
    return {};
}

std::string printable(std::string_view text, std::size_t max_chars) {
    std::string out;
    out.reserve(std::min(text.size(), max_chars) + 8);
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    std::size_t i = 0;
    while (i < text.size() && out.size() < max_chars) {
        const unsigned char c = byte(i);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
            ++i;
            continue;
        }
        // A well-formed UTF-8 sequence of a printable character (U+00A0 and up: the C1
        // controls U+0080..U+009F are escaped like the C0 ones) is kept as it is.
        const std::size_t len = c >= 0xF0 && c < 0xF5 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 ? 2 : 0;
        if (c < 0xF5 && len > 0 && i + len <= text.size()) {
            bool ok = true;
            for (std::size_t k = 1; k < len; ++k) ok = ok && (byte(i + k) & 0xC0) == 0x80;
            if (ok && !(c == 0xC2 && byte(i + 1) < 0xA0)) {
                out.append(text.substr(i, len));
                i += len;
                continue;
            }
        }
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", c);
        out += hex;
        ++i;
    }
    if (i < text.size()) out += "... (" + std::to_string(text.size() - i) + " more bytes)";
    return out;
}

}  // namespace maxslice::core
