// Whole-file reading and writing shared by the library and the programs. Writes go to a
// scratch file of a unique name and are renamed, so a failed write never leaves a partial file
// and never touches another one.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rt/util/huge_pages.h"
#include "rt/util/limits.h"

namespace rt {

/// Reads a regular file whole (into a buffer of the size the file has). False when it cannot be
/// read, with the reason in *why when given (see regular_file_error). A FIFO, a device or a
/// directory is never opened for reading (a FIFO would block, /dev/zero never ends): it is refused,
/// and so is a file of the kernel's pseudo file systems (/proc, /sys, debugfs, ...: their files
/// are the process's environment and memory maps, never scene data), a file over kMaxFileBytes,
/// and one that grows by more than kMaxFileGrowth while it is read.
bool read_file(const std::string& path, std::string* out, std::string* why = nullptr);

/// HugePageAllocator whose elements are default-initialised: a buffer that is about to be read
/// into is not zero-filled first.
template <class T>
struct UninitialisedHugePageAllocator : HugePageAllocator<T> {
    template <class U>
    struct rebind {
        using other = UninitialisedHugePageAllocator<U>;
    };
    UninitialisedHugePageAllocator() = default;
    template <class U>
    UninitialisedHugePageAllocator(const UninitialisedHugePageAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
};

/// A whole file's bytes, as the scene parser reads them: a large file lands in huge pages, and is
/// copied once (from the page cache), never zero-filled before (a million-triangle scene is 80 MB).
using FileBytes = std::vector<char, UninitialisedHugePageAllocator<char>>;
bool read_file(const std::string& path, FileBytes* out, std::string* why = nullptr);
inline std::string_view text_of(const FileBytes& bytes) { return {bytes.data(), bytes.size()}; }

/// Empty when `path` names a regular file that can be opened for reading, else why not:
/// "cannot open 'x': No such file or directory", "'x' is a FIFO, not a regular file". Opens
/// without blocking, so a FIFO is never waited on. Readers that open files themselves (streams,
/// OpenEXR) call it first.
std::string regular_file_error(const std::string& path);

/// Empty when a file can be written at `path`, else why not: a scratch file is made beside it
/// and removed (no file of the user's is touched), so a run can refuse an output it could not
/// write before it works: "cannot write 'x': it is a directory", "cannot write 'x': No such file
/// or directory".
std::string writable_error(const std::string& path);

/// Creates a new, empty file beside `path` (in its directory) under a name no other file has:
/// ".NAME.XXXXXX" plus `suffix` (".tmp" unless given: ffmpeg, say, needs the extension). It is
/// created exclusively (O_EXCL), so it never truncates or replaces an existing file, with the
/// permissions a new file gets (0666 less the umask). Returns its name, and its descriptor in
/// *fd (else it is closed). Throws std::runtime_error ("cannot write 'path': why").
std::string create_scratch_file(const std::string& path, int* fd = nullptr,
                                const std::string& suffix = ".tmp");

/// Renames a scratch file to `path` (or, when that fails, removes it and throws "cannot write
/// 'path': why"). A scratch file is registered while it exists: a SIGINT, SIGTERM or SIGHUP
/// that arrives meanwhile removes it before it ends the process (where the program has no
/// handler of its own for that signal). Only SIGKILL, a crash or a power cut can leave one,
/// under its own hidden name (".NAME.XXXXXX.tmp"), never as `path`.
void commit_scratch_file(const std::string& scratch, const std::string& path);
/// Removes a scratch file that is not wanted after all.
void discard_scratch_file(const std::string& scratch);
/// The child process that writes a scratch file (ffmpeg encoding a video), or 0 once it ended: a
/// signal that removes the scratch files stops it first (SIGTERM, and waits for it), so that it
/// cannot write its file again once removed.
void set_scratch_writer(int pid);

/// Writes `data` to a new scratch file beside `path` (create_scratch_file) and returns its
/// name, for the caller to commit to `path` when everything it writes is ready (or to discard).
/// Throws std::runtime_error ("cannot write 'path': why") and leaves nothing behind on failure.
std::string write_scratch_file(const std::string& path, const std::string& data);

/// Writes `data` to a scratch file beside `path` (write_scratch_file), checks the close, then
/// renames it to `path`, so `path` is either the old file or the whole new one, and no other
/// file is touched. Throws std::runtime_error ("cannot write 'path': why") and removes the
/// scratch file on failure.
void write_file_atomic(const std::string& path, const std::string& data);

}  // namespace rt
