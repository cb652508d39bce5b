// Runs a reader in a forked child process. Open CASCADE dereferences null handles on some
// damaged STEP files (found by fuzz/fuzz_step: StepGeom_CartesianPoint::NbCoordinates on a
// point that is not there) and any library may take unbounded time on a hostile file; a
// library cannot catch a segmentation fault, and installing process-wide signal handlers
// from a library would fight with the application's and the sanitizers'. In a child, a
// crash or a time-out becomes a refusal of the file. read_mesh runs every reader that
// calls a third-party library this way (assimp, lib3mf, Open CASCADE); its own readers
// (STL, PLY, OFF) run in-process.
//
// The child runs the reader, writes the result (or the error) to a pipe and leaves with
// _exit, so no destructor, atexit handler or stdio buffer of the parent runs twice. Only the
// forking thread exists in the child; the reader must not rely on other threads (the
// tessellation runs sequentially).
//
// The child dies with its parent: the kernel sends it SIGKILL when the thread that forked it
// ends (PR_SET_PDEATHSIG; that thread waits for the child, so this is the parent's death),
// and a parent that died between fork and prctl is caught by comparing getppid() with the
// parent's pid. Otherwise a killed slicer would leave a reader running with no time limit.
//
// The child's memory is bounded too (kReaderMemoryShare of the machine's, by RLIMIT_AS): a
// small compressed 3MF can inflate to gigabytes of XML, and a reader that runs out of its
// share fails with std::bad_alloc, a refusal that names the cause, instead of pushing the
// machine into swap or the kernel's OOM killer. AddressSanitizer reserves terabytes of
// address space for its shadow memory, so sanitizer builds leave the bound out.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <new>
#include <string>

#include "readers.hpp"

namespace maxslice::io::detail {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// Lowers the child's address-space limit to its share of the machine's memory.
void bound_memory() {
    if (kAddressSanitizer) return;
    const double bytes = kReaderMemoryShare * static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                         static_cast<double>(::sysconf(_SC_PAGESIZE));
    struct rlimit lim {};
    if (!(bytes > 0.0) || ::getrlimit(RLIMIT_AS, &lim) != 0) return;
    const auto want = static_cast<rlim_t>(bytes);
    if (lim.rlim_cur == RLIM_INFINITY || lim.rlim_cur > want) {
        lim.rlim_cur = want;
        ::setrlimit(RLIMIT_AS, &lim);
    }
}

class Writer {
public:
    void u64(std::uint64_t v) { raw(&v, sizeof v); }
    void str(std::string_view s) {
        u64(s.size());
        raw(s.data(), s.size());
    }
    void raw(const void* p, std::size_t n) { out_.append(static_cast<const char*>(p), n); }
    [[nodiscard]] const std::string& bytes() const { return out_; }

private:
    std::string out_;
};

class Reader {
public:
    explicit Reader(std::string_view in) : in_(in) {}
    bool u64(std::uint64_t& v) { return raw(&v, sizeof v); }
    bool str(std::string& s) {
        std::uint64_t n = 0;
        if (!u64(n) || n > in_.size() - pos_) return false;
        s.assign(in_.substr(pos_, n));
        pos_ += n;
        return true;
    }
    bool raw(void* p, std::size_t n) {
        if (n > in_.size() - pos_) return false;
        std::memcpy(p, in_.data() + pos_, n);
        pos_ += n;
        return true;
    }
    [[nodiscard]] bool done() const { return pos_ == in_.size(); }

private:
    std::string_view in_;
    std::size_t pos_ = 0;
};

std::string encode(const core::Result<RawImport>& result) {
    Writer w;
    if (!result) {
        w.u64(0);
        w.u64(static_cast<std::uint64_t>(result.error().code));
        w.str(result.error().message);
        w.str(result.error().context);
        return w.bytes();
    }
    const RawImport& r = *result;
    w.u64(1);
    w.u64(static_cast<std::uint64_t>(r.format));
    w.u64(r.converted_to_mm ? 1 : 0);
    w.u64(r.declared_unit ? 1 + static_cast<std::uint64_t>(*r.declared_unit) : 0);
    w.str(r.declared_unit_text);
    w.u64(r.solids);
    w.u64(r.warnings.size());
    for (const std::string& s : r.warnings) w.str(s);
    w.u64(r.mesh.vertices.size());
    w.raw(r.mesh.vertices.data(), r.mesh.vertices.size() * sizeof(core::Vec3d));
    w.u64(r.mesh.triangles.size());
    w.raw(r.mesh.triangles.data(), r.mesh.triangles.size() * sizeof(mesh::Triangle));
    return w.bytes();
}

std::optional<core::Result<RawImport>> decode(std::string_view bytes) {
    Reader rd(bytes);
    std::uint64_t ok = 0;
    if (!rd.u64(ok)) return std::nullopt;
    if (ok == 0) {
        std::uint64_t code = 0;
        core::Error e;
        if (!rd.u64(code) || !rd.str(e.message) || !rd.str(e.context) || !rd.done()) {
            return std::nullopt;
        }
        e.code = static_cast<core::ErrorCode>(code);
        return core::Result<RawImport>(std::unexpected(std::move(e)));
    }
    RawImport r;
    std::uint64_t format = 0, converted = 0, unit = 0, count = 0;
    if (!rd.u64(format) || !rd.u64(converted) || !rd.u64(unit) || !rd.str(r.declared_unit_text) ||
        !rd.u64(count)) {
        return std::nullopt;
    }
    r.format = static_cast<Format>(format);
    r.converted_to_mm = converted != 0;
    if (unit != 0) r.declared_unit = static_cast<core::LengthUnit>(unit - 1);
    r.solids = count;
    if (!rd.u64(count) || count > bytes.size()) return std::nullopt;
    r.warnings.resize(count);
    for (std::string& s : r.warnings) {
        if (!rd.str(s)) return std::nullopt;
    }
    if (!rd.u64(count) || count > bytes.size() / sizeof(core::Vec3d)) return std::nullopt;
    r.mesh.vertices.resize(count);
    if (!rd.raw(r.mesh.vertices.data(), count * sizeof(core::Vec3d))) return std::nullopt;
    if (!rd.u64(count) || count > bytes.size() / sizeof(mesh::Triangle)) return std::nullopt;
    r.mesh.triangles.resize(count);
    if (!rd.raw(r.mesh.triangles.data(), count * sizeof(mesh::Triangle)) || !rd.done()) {
        return std::nullopt;
    }
    return core::Result<RawImport>(std::move(r));
}

void write_all(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t n = ::write(fd, bytes.data(), bytes.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            return;
        }
        bytes.remove_prefix(static_cast<std::size_t>(n));
    }
}

}  // namespace

core::Result<RawImport> run_isolated(const std::function<core::Result<RawImport>()>& reader,
                                     double time_limit_s, std::string_view library,
                                     std::string_view slow_because) {
    const pid_t parent = ::getpid();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) {
        return core::fail(core::ErrorCode::kIo, fmt::format("cannot start the {} reader: {}",
                                                            library, std::strerror(errno)));
    }
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int err = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return core::fail(core::ErrorCode::kIo, fmt::format("cannot start the {} reader: {}",
                                                            library, std::strerror(err)));
    }
    if (pid == 0) {
        if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(1);
        ::close(fds[0]);
        bound_memory();
        std::string bytes;
        try {
            bytes = encode(reader());
        } catch (const std::bad_alloc&) {
            bytes = encode(core::fail(
                core::ErrorCode::kInvalidInput,
                fmt::format("{} ran out of the memory a part reader may use ({:.0f}% of the "
                            "machine's) reading the file: it expands to more than that (a "
                            "packed file that inflates enormously, or a damaged one)",
                            library, 100.0 * kReaderMemoryShare)));
        } catch (...) {
            bytes = encode(core::fail(core::ErrorCode::kInvalidInput,
                                      fmt::format("{} failed to read the file", library)));
        }
        write_all(fds[1], bytes);
        ::close(fds[1]);
        ::_exit(0);
    }

    ::close(fds[1]);
    std::string bytes;
    bool timed_out = false;
    const auto start = std::chrono::steady_clock::now();
    char buffer[1 << 16];
    while (true) {
        int wait_ms = -1;
        if (time_limit_s > 0.0) {
            const double left =
                time_limit_s -
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (left <= 0.0) {
                timed_out = true;
                break;
            }
            wait_ms = static_cast<int>(std::min(left * 1000.0 + 1.0, 1e9));
        }
        pollfd p{fds[0], POLLIN, 0};
        const int ready = ::poll(&p, 1, wait_ms);
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) continue;  // the time check above decides
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        bytes.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(fds[0]);
    if (timed_out) ::kill(pid, SIGKILL);
    int status = 0;
    pid_t waited = -1;
    do {
        waited = ::waitpid(pid, &status, 0);
    } while (waited < 0 && errno == EINTR);

    if (timed_out) {
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} did not finish reading the file within the {} s "
                                      "limit for a part reader and was stopped: {}",
                                      library, time_limit_s, slow_because));
    }
    if (waited == pid && WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        return core::fail(core::ErrorCode::kInvalidInput,
                          fmt::format("{} crashed reading the file (signal {}: {}); the file is "
                                      "probably damaged: repair it or export it again",
                                      library, sig, ::strsignal(sig)));
    }
    // waitpid may fail with ECHILD when the application ignores SIGCHLD; the payload then
    // decides alone.
    if (auto result = decode(bytes)) return std::move(*result);
    return core::fail(core::ErrorCode::kInvalidInput,
                      fmt::format("{} stopped before it finished reading the file", library));
}

}  // namespace maxslice::io::detail
