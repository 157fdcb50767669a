#include "rt/util/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>
#include <stdexcept>

namespace rt {

namespace {

const char* kind_of(mode_t mode) {
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

// The kernel's pseudo file systems, by statfs's f_type (linux/magic.h): their "regular" files
// are windows onto the kernel and the process (/proc/self/environ, /proc/self/pagemap, whose reads
// go on far past its size of 0), never scene data.
struct PseudoFileSystem {
    unsigned long magic;
    const char* name;
};
constexpr PseudoFileSystem kPseudoFileSystems[] = {
    {0x9fa0, "/proc"},           {0x62656572, "sysfs"},      {0x64626720, "debugfs"},
    {0x74726163, "tracefs"},     {0x73636673, "securityfs"}, {0x27e0eb, "cgroup"},
    {0x63677270, "cgroup2"},     {0x62656570, "configfs"},   {0xde5e81e4, "efivarfs"},
    {0xcafe4a11, "bpf"},         {0x6165676c, "pstore"},     {0x1cd1, "devpts"},
    {0x42494e4d, "binfmt_misc"},
};

// Null when `type` is an ordinary file system.
const char* pseudo_file_system(long type) {
    for (const PseudoFileSystem& p : kPseudoFileSystems)
        if (static_cast<unsigned long>(type) == p.magic) return p.name;
    return nullptr;
}

// Opens `path` for reading without blocking (O_NONBLOCK: opening a FIFO with no writer would wait
// forever) and checks that it is a regular file. Returns the descriptor, or -1 with *why set.
int open_regular(const std::string& path, struct stat* st, std::string* why) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        *why = "cannot open '" + path + "': " + std::strerror(errno);
        return -1;
    }
    if (::fstat(fd, st) != 0) {
        *why = "cannot open '" + path + "': " + std::strerror(errno);
        ::close(fd);
        return -1;
    }
    if (!S_ISREG(st->st_mode)) {
        *why = "'" + path + "' is " + kind_of(st->st_mode) + ", not a regular file";
        ::close(fd);
        return -1;
    }
    struct statfs fs {};
    if (::fstatfs(fd, &fs) == 0) {
        if (const char* name = pseudo_file_system(fs.f_type)) {
            *why = "'" + path + "' is a file of the kernel (in " + name + "), not a regular file";
            ::close(fd);
            return -1;
        }
    }
    if (static_cast<uint64_t>(st->st_size) > kMaxFileBytes) {
        *why = "'" + path + "' is " + std::to_string(st->st_size) +
               " bytes, larger than the largest file read (" + std::to_string(kMaxFileBytes) +
               " bytes)";
        ::close(fd);
        return -1;
    }
    return fd;
}

}  // namespace

std::string regular_file_error(const std::string& path) {
    struct stat st {};
    std::string why;
    const int fd = open_regular(path, &st, &why);
    if (fd >= 0) ::close(fd);
    return why;
}

namespace {

template <class Buffer>
bool read_whole(const std::string& path, Buffer* out, std::string* why) {
    std::string reason;
    struct stat st {};
    const int fd = open_regular(path, &st, &reason);
    out->clear();
    if (fd >= 0) {
        // The size from fstat sizes the buffer, which is filled first; only what a file that
        // grew meanwhile adds goes through a small buffer (growing the whole one to probe for the
        // end would double the memory of every read), and no more than kMaxFileGrowth of it: a
        // file whose reads do not end at its size is refused, not read until memory runs out.
        out->resize(static_cast<size_t>(st.st_size));
        size_t done = 0;
        char extra[4096];
        for (;;) {
            const bool in_place = done < out->size();
            const ssize_t n = in_place ? ::read(fd, out->data() + done, out->size() - done)
                                       : ::read(fd, extra, sizeof extra);
            if (n > 0) {
                if (!in_place) {
                    if (done + static_cast<size_t>(n) >
                        static_cast<size_t>(st.st_size) + kMaxFileGrowth) {
                        reason =
                            "'" + path + "' grew by more than " + std::to_string(kMaxFileGrowth) +
                            " bytes while it was read (from " + std::to_string(st.st_size) + ")";
                        break;
                    }
                    out->insert(out->end(), extra, extra + n);
                }
                done += static_cast<size_t>(n);
            } else if (n == 0) {
                break;
            } else if (errno != EINTR) {
                reason = "cannot read '" + path + "': " + std::strerror(errno);
                break;
            }
        }
        out->resize(reason.empty() ? done : 0);
        ::close(fd);
    }
    if (why) *why = reason;
    return reason.empty();
}

}  // namespace

bool read_file(const std::string& path, std::string* out, std::string* why) {
    return read_whole(path, out, why);
}

bool read_file(const std::string& path, FileBytes* out, std::string* why) {
    return read_whole(path, out, why);
}

// ---- scratch files and the signals that would leave them ---------------------------------------
namespace {

// The scratch files that exist now, for the handler of SIGINT, SIGTERM and SIGHUP to remove before
// the signal ends the process (a Ctrl-C during a write, a job killed by its scheduler). Fixed
// slots of fixed size: the handler may only read memory and call unlink(), which is
// async-signal-safe; a slot's path is written before the slot is marked live and never freed.
constexpr size_t kScratchSlots = 64;
struct ScratchSlot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
    char path[PATH_MAX];
};
std::array<ScratchSlot, kScratchSlots> g_scratch;

// The child process writing one of them (ffmpeg encoding a video), or 0.
std::atomic<pid_t> g_scratch_writer{0};

void remove_scratch_files_and_reraise(int sig) {
    // The child first (kill and waitpid are async-signal-safe): left running, it would write its
    // file again after it is removed.
    if (const pid_t child = g_scratch_writer.load(std::memory_order_acquire); child > 0) {
        ::kill(child, SIGTERM);
        while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
        }
    }
    for (ScratchSlot& s : g_scratch)
        if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
    // The default action, as if we had never been here: the process ends by the signal.
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

// Installed once, for each signal whose action is still the default (a program with handlers of
// its own, such as rayview's clean quit, keeps them; an ignored signal stays ignored).
void install_scratch_handlers() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction old {};
            if (::sigaction(sig, nullptr, &old) != 0) continue;
            if ((old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) continue;
            struct sigaction sa {};
            sa.sa_handler = remove_scratch_files_and_reraise;
            sigemptyset(&sa.sa_mask);
            ::sigaction(sig, &sa, nullptr);
        }
    });
}

// Registers a scratch file (a path too long for a slot, or all slots taken: not registered, so
// only a signal could leave it, as before).
void track_scratch(const std::string& name) {
    if (name.size() >= PATH_MAX) return;
    install_scratch_handlers();
    for (ScratchSlot& s : g_scratch) {
        int expected = 0;
        if (!s.state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) continue;
        std::memcpy(s.path, name.c_str(), name.size() + 1);
        s.state.store(2, std::memory_order_release);
        return;
    }
}

void untrack_scratch(const std::string& name) {
    for (ScratchSlot& s : g_scratch) {
        if (s.state.load(std::memory_order_acquire) != 2 || name != s.path) continue;
        int expected = 2;
        if (s.state.compare_exchange_strong(expected, 0, std::memory_order_acq_rel)) return;
    }
}

}  // namespace

void set_scratch_writer(int pid) {
    g_scratch_writer.store(static_cast<pid_t>(pid), std::memory_order_release);
}

void commit_scratch_file(const std::string& scratch, const std::string& path) {
    if (::rename(scratch.c_str(), path.c_str()) != 0) {
        const int error = errno;
        discard_scratch_file(scratch);
        throw std::runtime_error("cannot write '" + path + "': " + std::strerror(error));
    }
    untrack_scratch(scratch);
}

void discard_scratch_file(const std::string& scratch) {
    ::unlink(scratch.c_str());
    untrack_scratch(scratch);
}

std::string create_scratch_file(const std::string& path, int* fd, const std::string& suffix) {
    // The rename would replace a FIFO or a device (/dev/null as root) by the file.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
        throw std::runtime_error("cannot write '" + path + "': it is " + kind_of(st.st_mode) +
                                 ", not a regular file");
    const std::filesystem::path target(path);
    const std::string stem = target.parent_path().string();
    const std::string prefix =
        (stem.empty() ? "" : stem + "/") + "." + target.filename().string() + ".";
    // Seeded once a thread from the system's entropy: two processes (the ranks of a job, two
    // renders of one name) draw different names, and O_EXCL settles any clash that is left.
    thread_local std::mt19937_64 random(std::random_device{}() ^
                                        (static_cast<uint64_t>(::getpid()) << 32));
    constexpr char kChars[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = prefix;
        for (int i = 0; i < 6; ++i) name += kChars[random() % (sizeof kChars - 1)];
        name += suffix;
        // 0666: the kernel takes the umask off, as for any new file.
        // Created and registered with the signals held back, so that no moment passes when a
        // signal would leave it (registered after the open: a name taken by another file, which
        // O_EXCL refuses, is never registered, so never removed).
        const int f = [&] {
            sigset_t hold, old;
            sigemptyset(&hold);
            for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&hold, sig);
            ::pthread_sigmask(SIG_BLOCK, &hold, &old);
            const int opened = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            const int error = errno;  // (the open's, for the loop below)
            if (opened >= 0) track_scratch(name);
            ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
            errno = error;
            return opened;
        }();
        if (f >= 0) {
            if (fd)
                *fd = f;
            else
                ::close(f);
            return name;
        }
        if (errno != EEXIST) break;
    }
    throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
}

std::string writable_error(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        return "cannot write '" + path + "': it is a directory";
    try {
        discard_scratch_file(create_scratch_file(path));
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

std::string write_scratch_file(const std::string& path, const std::string& data) {
    int fd = -1;
    const std::string scratch = create_scratch_file(path, &fd);
    int error = 0;
    for (size_t done = 0; done < data.size() && !error;) {
        const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
        if (n >= 0)
            done += static_cast<size_t>(n);
        else if (errno != EINTR)
            error = errno;
    }
    // The close reports what a full disk or a quota kept back (NFS writes on close).
    if (::close(fd) != 0 && !error) error = errno;
    if (error) {
        discard_scratch_file(scratch);
        throw std::runtime_error("cannot write '" + path + "': " + std::strerror(error));
    }
    return scratch;
}

void write_file_atomic(const std::string& path, const std::string& data) {
    commit_scratch_file(write_scratch_file(path, data), path);
}

}  // namespace rt
