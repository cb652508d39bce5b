#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <new>
#include <string>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

class Fd {
public:
    explicit Fd(int fd) : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() {
        if (fd_ >= 0) ::close(fd_);
    }
    [[nodiscard]] int get() const { return fd_; }

private:
    int fd_;
};

std::string errno_text(int err) {
    return std::strerror(err);
}

// Opens a regular file and reports its size. O_NONBLOCK: opening a FIFO for reading blocks
// until a writer appears (forever, for a part file), and a device may block as well; with it
// the open returns at once and fstat refuses what is not a regular file. On a regular file
// O_NONBLOCK changes nothing (reads from disk never return EAGAIN).
core::Result<int> open_regular(const std::filesystem::path& path, std::uint64_t& size) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        const int err = errno;
        return core::fail(core::ErrorCode::kIo, "cannot open: " + errno_text(err));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int err = errno;
        ::close(fd);
        return core::fail(core::ErrorCode::kIo, "cannot read: " + errno_text(err));
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        return core::fail(core::ErrorCode::kIo,
                          S_ISDIR(st.st_mode)    ? "is a directory, not a part file"
                          : S_ISFIFO(st.st_mode) ? "is a FIFO (named pipe), not a regular file"
                                                 : "is not a regular file (a device or socket)");
    }
    size = static_cast<std::uint64_t>(st.st_size);
    return fd;
}

core::Result<std::size_t> read_into(int fd, char* out, std::size_t wanted) {
    std::size_t got = 0;
    while (got < wanted) {
        const ssize_t n = ::read(fd, out + got, wanted - got);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            return core::fail(core::ErrorCode::kIo, "read failed: " + errno_text(err));
        }
        if (n == 0) break;  // the file shrank while we read it
        got += static_cast<std::size_t>(n);
    }
    return got;
}

core::Result<FileBytes> read_prefix(const std::filesystem::path& path, std::uint64_t max_bytes,
                                    std::uint64_t& file_size) {
    auto fd_or = open_regular(path, file_size);
    if (!fd_or) return std::unexpected(fd_or.error());
    Fd fd(*fd_or);
    const std::uint64_t wanted = std::min(file_size, max_bytes);
    if (wanted > static_cast<std::uint64_t>(PTRDIFF_MAX)) {
        return core::fail(core::ErrorCode::kIo, "file too large to read into memory");
    }
    FileBytes bytes;
    // One allocation and one read for the whole file; +1 so that an empty file still gets
    // a valid pointer.
    bytes.data.reset(new (std::nothrow) char[static_cast<std::size_t>(wanted) + 1]);
    if (!bytes.data) {
        return core::fail(core::ErrorCode::kIo,
                          "not enough memory to read " + std::to_string(wanted) + " bytes");
    }
    auto got = read_into(fd.get(), bytes.data.get(), static_cast<std::size_t>(wanted));
    if (!got) return std::unexpected(got.error());
    bytes.size = *got;
    return bytes;
}

}  // namespace

core::Result<PositionalFile> PositionalFile::open(const std::filesystem::path& path) {
    std::uint64_t size = 0;
    auto fd = open_regular(path, size);
    if (!fd) return std::unexpected(fd.error());
    return PositionalFile(*fd);
}

PositionalFile::~PositionalFile() {
    if (fd_ >= 0) ::close(fd_);
}

core::Result<std::size_t> PositionalFile::read_at(std::uint64_t offset, char* out,
                                                  std::size_t bytes) const {
    std::size_t got = 0;
    while (got < bytes) {
        const ssize_t n = ::pread(fd_, out + got, bytes - got, static_cast<off_t>(offset + got));
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            return core::fail(core::ErrorCode::kIo, "read failed: " + errno_text(err));
        }
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    return got;
}

core::Result<FileBytes> read_file(const std::filesystem::path& path) {
    std::uint64_t size = 0;
    return read_prefix(path, UINT64_MAX, size);
}

core::Result<FileBytes> read_file_head(const std::filesystem::path& path, std::size_t max_bytes,
                                       std::uint64_t& file_size) {
    return read_prefix(path, max_bytes, file_size);
}

}  // namespace maxslice::io::detail
