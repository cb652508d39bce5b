// Runs a reader in a program of its own. Open CASCADE dereferences null handles on some
// damaged STEP files (found by fuzz/fuzz_step: StepGeom_CartesianPoint::NbCoordinates on a
// point that is not there) and any library may take unbounded time on a hostile file; a
// library cannot catch a segmentation fault, and installing process-wide signal handlers
// from a library would fight with the application's and the sanitizers'. In a process of
// its own, a crash or a time-out becomes a refusal of the file. read_mesh reads every format
// that goes through a third-party library (assimp, lib3mf, Open CASCADE) this way, in the
// program maxslice-read-part (read_part_main.cpp); its own readers (STL, PLY, OFF) run
// in-process.
//
// The reader is a program started with posix_spawn, not a fork of the caller running the
// reader: the caller has threads (a thread pool that a library starts when it is loaded, the
// job's own), and a forked child holds only the forking thread, with every lock another
// thread held at that moment held for ever. A fork taken while such a thread was inside the
// allocator hung the child until the reader's time limit (seen under AddressSanitizer, whose
// allocator clang 16 does not prepare for fork). A new program starts with one thread and
// nothing locked.
//
// The program writes the result (or the error) to descriptor 3, a pipe the caller reads,
// and leaves with _exit. It dies with its caller: it asks the kernel for SIGKILL when the
// thread that started it ends (PR_SET_PDEATHSIG; that thread waits for it, so this is the
// caller's death), and a caller that died before the request is caught by comparing
// getppid() with the caller's pid, which the caller passes as the first argument. Otherwise
// a killed slicer would leave a reader running with no time limit.
//
// The program's memory is bounded too (kReaderMemoryShare of the machine's, by RLIMIT_AS): a
// small compressed 3MF can inflate to gigabytes of XML, and a reader that runs out of its
// share fails with std::bad_alloc, a refusal that names the cause, instead of pushing the
// machine into swap or the kernel's OOM killer. AddressSanitizer reserves terabytes of
// address space for its shadow memory, so sanitizer builds leave the bound out.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "readers.hpp"

#if MAXSLICE_ADDRESS_SANITIZER
#include <sanitizer/common_interface_defs.h>
#endif

namespace maxslice::io::detail {
namespace {

// Lowers the child's address-space limit to its share of the machine's memory.
void bound_memory() {
    if (MAXSLICE_ADDRESS_SANITIZER) return;
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

// The first word of what the reader program writes.
enum class Payload : std::uint64_t {
    kError = 0,
    kMesh = 1,
    kOutOfMemory = 2,
    kThrew = 3,
    kSanitizer = 4,  ///< a sanitizer reported an error in the reader (sanitizer builds)
};

std::string encode(Payload tag) {
    Writer w;
    w.u64(static_cast<std::uint64_t>(tag));
    return w.bytes();
}

std::string encode(const core::Result<RawImport>& result) {
    Writer w;
    if (!result) {
        w.u64(static_cast<std::uint64_t>(Payload::kError));
        w.u64(static_cast<std::uint64_t>(result.error().code));
        w.str(result.error().message);
        w.str(result.error().context);
        return w.bytes();
    }
    const RawImport& r = *result;
    w.u64(static_cast<std::uint64_t>(Payload::kMesh));
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

std::optional<core::Result<RawImport>> decode(std::string_view bytes, std::string_view library) {
    Reader rd(bytes);
    std::uint64_t tag = 0;
    if (!rd.u64(tag)) return std::nullopt;
    if (tag == static_cast<std::uint64_t>(Payload::kOutOfMemory) && rd.done()) {
        return core::Result<RawImport>(core::fail(
            core::ErrorCode::kInvalidInput,
            fmt::format("{} ran out of the memory a part reader may use ({:.0f}% of the "
                        "machine's) reading the file: it expands to more than that (a packed "
                        "file that inflates enormously, or a damaged one)",
                        library, 100.0 * kReaderMemoryShare)));
    }
    if (tag == static_cast<std::uint64_t>(Payload::kSanitizer)) {
        return core::Result<RawImport>(core::fail(
            core::ErrorCode::kInternal,
            fmt::format("the {} reader program stopped on a sanitizer report (printed above): a "
                        "bug in maxslice's reading code, not in the file",
                        library)));
    }
    if (tag == static_cast<std::uint64_t>(Payload::kThrew) && rd.done()) {
        return core::Result<RawImport>(core::fail(
            core::ErrorCode::kInvalidInput, fmt::format("{} failed to read the file", library)));
    }
    if (tag == static_cast<std::uint64_t>(Payload::kError)) {
        std::uint64_t code = 0;
        core::Error e;
        if (!rd.u64(code) || !rd.str(e.message) || !rd.str(e.context) || !rd.done()) {
            return std::nullopt;
        }
        e.code = static_cast<core::ErrorCode>(code);
        return core::Result<RawImport>(std::unexpected(std::move(e)));
    }
    if (tag != static_cast<std::uint64_t>(Payload::kMesh)) return std::nullopt;
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

// The descriptor the reader program writes its result to.
constexpr int kResultFd = 3;

// Moves a descriptor above kResultFd (close-on-exec), so that the child's dup2 onto
// kResultFd always makes a new descriptor, one that exec keeps.
int above_result_fd(int fd) {
    if (fd > kResultFd) return fd;
    const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, kResultFd + 1);
    ::close(fd);
    return moved;
}

// Ends the reader program with what it has to say.
[[noreturn]] void leave_with(std::string_view bytes) {
    write_all(kResultFd, bytes);
    ::close(kResultFd);
    ::_exit(0);
}

#if MAXSLICE_ADDRESS_SANITIZER
// Called by the sanitizer runtime when it ends the reader program on a report (a bug in
// maxslice's own code that runs there: AddressSanitizer, or UndefinedBehaviorSanitizer
// without recovery): the caller learns that it was a report, not a crash of the library on
// a damaged file, whichever way the runtime then ends the program (abort_on_error).
void sanitizer_died() {
    const auto tag = static_cast<std::uint64_t>(Payload::kSanitizer);
    [[maybe_unused]] const ssize_t n = ::write(kResultFd, &tag, sizeof tag);
}
#endif

}  // namespace

core::Result<RawImport> run_isolated(const ReaderCommand& command, double time_limit_s,
                                     std::string_view library, std::string_view slow_because) {
    const auto cannot_start = [&](int err) {
        return core::fail(core::ErrorCode::kIo,
                          fmt::format("cannot start the {} reader {}: {}", library,
                                      command.program.string(), std::strerror(err)));
    };
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return cannot_start(errno);
    fds[0] = above_result_fd(fds[0]);
    fds[1] = above_result_fd(fds[1]);
    if (fds[0] < 0 || fds[1] < 0) {
        const int err = errno;
        if (fds[0] >= 0) ::close(fds[0]);
        if (fds[1] >= 0) ::close(fds[1]);
        return cannot_start(err);
    }

    std::vector<std::string> args;
    args.reserve(command.args.size() + 2);
    args.push_back(command.program.string());
    args.push_back(std::to_string(::getpid()));
    args.insert(args.end(), command.args.begin(), command.args.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attr;
    ::posix_spawn_file_actions_init(&actions);
    ::posix_spawn_file_actions_adddup2(&actions, fds[1], kResultFd);
    ::posix_spawnattr_init(&attr);
    // The program starts with no signal blocked, whatever the calling thread blocks.
    sigset_t none;
    sigemptyset(&none);
    ::posix_spawnattr_setsigmask(&attr, &none);
    ::posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
    pid_t pid = -1;
    const int spawned =
        ::posix_spawn(&pid, command.program.c_str(), &actions, &attr, argv.data(), environ);
    ::posix_spawnattr_destroy(&attr);
    ::posix_spawn_file_actions_destroy(&actions);
    ::close(fds[1]);
    if (spawned != 0) {
        ::close(fds[0]);
        return cannot_start(spawned);
    }

    std::string bytes;
    bool timed_out = false;
    const auto start = std::chrono::steady_clock::now();
    std::array<char, 1 << 16> buffer{};
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
        const ssize_t n = ::read(fds[0], buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        bytes.append(buffer.data(), static_cast<std::size_t>(n));
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
    // A sanitizer report ends the program with a signal or an exit code the runtime's options
    // choose: what it wrote says which.
    std::uint64_t tag = 0;
    if (bytes.size() >= sizeof tag) std::memcpy(&tag, bytes.data(), sizeof tag);
    if (tag == static_cast<std::uint64_t>(Payload::kSanitizer)) {
        if (auto result = decode(bytes, library)) return std::move(*result);
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
    if (auto result = decode(bytes, library)) return std::move(*result);
    return core::fail(core::ErrorCode::kInvalidInput,
                      fmt::format("{} stopped before it finished reading the file", library));
}

void serve_isolated(int argc, char** argv, const IsolatedReader& reader) {
    if (::fcntl(kResultFd, F_GETFD) < 0) ::_exit(2);  // not started by run_isolated
    pid_t parent = 0;
    const std::string_view pid_text = argc > 1 ? argv[1] : "";
    const auto parsed = std::from_chars(pid_text.data(), pid_text.data() + pid_text.size(), parent);
    if (parsed.ec != std::errc() || parsed.ptr != pid_text.data() + pid_text.size()) {
        ::_exit(2);
    }
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(1);
    bound_memory();
#if MAXSLICE_ADDRESS_SANITIZER
    __sanitizer_set_death_callback(&sanitizer_died);
#endif
    std::vector<std::string_view> args;
    for (int i = 2; i < argc; ++i) args.emplace_back(argv[i]);
    try {
        leave_with(encode(reader(args)));
    } catch (const std::bad_alloc&) {
        leave_with(encode(Payload::kOutOfMemory));
    } catch (...) {
        leave_with(encode(Payload::kThrew));
    }
}

}  // namespace maxslice::io::detail
