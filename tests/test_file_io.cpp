// Whole-file reads and writes: only regular files are read, and a write touches no file but its
// own (its scratch file has a name of its own, with a new file's permissions, and goes on failure).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "rt/util/file_io.h"

namespace fs = std::filesystem;
using rt::read_file;
using rt::write_file_atomic;

namespace {

std::string contents(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

// A fresh empty directory under the test's temporary directory.
fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::path(::testing::TempDir()) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

size_t entries(const fs::path& dir) {
    return static_cast<size_t>(std::distance(fs::directory_iterator(dir), {}));
}

}  // namespace

TEST(FileIo, ReadRefusesAFifoWithTheReason) {
    const fs::path dir = fresh_dir("rt_io_fifo");
    const std::string fifo = (dir / "scene.ray").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string text, why;
    EXPECT_FALSE(read_file(fifo, &text, &why));  // returns: the FIFO has no writer
    EXPECT_EQ(why, "'" + fifo + "' is a FIFO, not a regular file");
    EXPECT_EQ(rt::regular_file_error(fifo), why);
}

// The parser's buffer (not zero-filled, in huge pages when large) holds the file's bytes
// exactly, whatever their values, at both sizes; what it held before is gone.
TEST(FileIo, FileBytesHoldTheFileExactly) {
    const fs::path dir = fresh_dir("rt_io_bytes");
    for (const size_t size : {size_t{0}, size_t{1000}, size_t{5} << 20}) {
        std::string data(size, '\0');
        for (size_t i = 0; i < size; ++i) data[i] = static_cast<char>((i * 7919) >> 3);
        const std::string path = (dir / ("f" + std::to_string(size))).string();
        write_file_atomic(path, data);
        rt::FileBytes bytes(123, 'x');
        std::string why;
        ASSERT_TRUE(read_file(path, &bytes, &why)) << why;
        EXPECT_EQ(rt::text_of(bytes), data) << size;
    }
    rt::FileBytes bytes(10, 'x');
    std::string why;
    EXPECT_FALSE(read_file((dir / "missing").string(), &bytes, &why));
    EXPECT_TRUE(bytes.empty());
    EXPECT_NE(why.find("No such file"), std::string::npos) << why;
}

TEST(FileIo, WriteLeavesAFileNamedLikeItsScratchFileAlone) {
    // NAME.part was the scratch name: an input of that name was truncated, then renamed away.
    const fs::path dir = fresh_dir("rt_io_part");
    std::ofstream(dir / "img.pfm.part") << "a part file";
    write_file_atomic((dir / "img.pfm").string(), "the image");
    EXPECT_EQ(contents(dir / "img.pfm"), "the image");
    EXPECT_EQ(contents(dir / "img.pfm.part"), "a part file");
    EXPECT_EQ(entries(dir), 2u);  // and no scratch file is left
}

TEST(FileIo, ScratchFilesHaveNamesOfTheirOwn) {
    const fs::path dir = fresh_dir("rt_io_scratch");
    const std::string target = (dir / "out.png").string();
    const std::string a = rt::create_scratch_file(target);
    const std::string b = rt::create_scratch_file(target, nullptr, ".mp4");
    EXPECT_NE(a, b);
    EXPECT_EQ(fs::path(a).parent_path(), dir);
    EXPECT_EQ(fs::path(a).filename().string().rfind(".out.png.", 0), 0u) << a;
    EXPECT_EQ(fs::path(a).extension(), ".tmp");
    EXPECT_EQ(fs::path(b).extension(), ".mp4");
    EXPECT_FALSE(fs::exists(target));
}

TEST(FileIo, WrittenFilesGetTheUmasksPermissions) {
    const fs::path dir = fresh_dir("rt_io_mode");
    const mode_t old = ::umask(022);
    write_file_atomic((dir / "a.txt").string(), "a");
    ::umask(027);
    write_file_atomic((dir / "b.txt").string(), "b");
    ::umask(old);
    struct stat st {};
    ASSERT_EQ(::stat((dir / "a.txt").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0644u);
    ASSERT_EQ(::stat((dir / "b.txt").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0640u);
}

TEST(FileIo, AFailedWriteLeavesNothing) {
    const fs::path dir = fresh_dir("rt_io_fail");
    fs::create_directory(dir / "taken");  // a directory where the file would go
    try {
        write_file_atomic((dir / "taken").string(), "data");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot write '" + (dir / "taken").string() + "'"),
                  std::string::npos);
    }
    EXPECT_TRUE(fs::is_directory(dir / "taken"));
    EXPECT_EQ(entries(dir), 1u);
    EXPECT_THROW(write_file_atomic((dir / "none" / "x.txt").string(), "data"), std::runtime_error);
    EXPECT_EQ(entries(dir), 1u);
}

TEST(FileIo, WriteRefusesToReplaceAFifo) {
    const fs::path dir = fresh_dir("rt_io_wfifo");
    const std::string fifo = (dir / "out.png").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    try {
        write_file_atomic(fifo, "data");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "cannot write '" + fifo + "': it is a FIFO, not a regular file");
    }
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_EQ(entries(dir), 1u);
}

// The kernel's files look regular but are the process's environment and memory: an error names
// the file system, never the file's bytes, and /proc/self/pagemap (whose reads would go on until
// memory runs out) is never read.
TEST(FileIo, ReadRefusesTheKernelsPseudoFiles) {
    for (const std::string path :
         {"/proc/self/environ", "/proc/self/pagemap", "/proc/self/status"}) {
        if (!fs::exists(path)) continue;
        std::string text = "before", why;
        EXPECT_FALSE(read_file(path, &text, &why)) << path;
        EXPECT_EQ(why, "'" + path + "' is a file of the kernel (in /proc), not a regular file");
        EXPECT_TRUE(text.empty());
        EXPECT_EQ(rt::regular_file_error(path), why);
    }
    const std::string sys = "/sys/kernel/mm/transparent_hugepage/enabled";
    if (fs::is_regular_file(sys)) {
        std::string text, why;
        EXPECT_FALSE(read_file(sys, &text, &why));
        EXPECT_EQ(why, "'" + sys + "' is a file of the kernel (in sysfs), not a regular file");
    }
}

// A file over the largest size read is refused with its size before a byte is read (a sparse
// file: no disk is used).
TEST(FileIo, ReadRefusesAFileOverTheLargestSize) {
    const fs::path dir = fresh_dir("rt_io_huge");
    const std::string path = (dir / "huge.ray").string();
    { std::ofstream(path) << "x"; }
    fs::resize_file(path, rt::kMaxFileBytes + 1);
    rt::FileBytes bytes;
    std::string why;
    EXPECT_FALSE(read_file(path, &bytes, &why));
    EXPECT_EQ(why, "'" + path + "' is " + std::to_string(rt::kMaxFileBytes + 1) +
                       " bytes, larger than the largest file read (" +
                       std::to_string(rt::kMaxFileBytes) + " bytes)");
    EXPECT_EQ(bytes.capacity(), 0u);
    fs::remove(path);
}

// A SIGINT, SIGTERM or SIGHUP while a scratch file exists (a Ctrl-C during a write) removes it
// before the signal ends the process; the file already there keeps its bytes.
TEST(FileIo, ASignalDuringAWriteLeavesNoScratchFile) {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
        const fs::path dir = fresh_dir("rt_io_signal_" + std::to_string(sig));
        const std::string out = (dir / "out.png").string();
        write_file_atomic(out, "the old image");
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            int fd = -1;
            const std::string scratch = rt::create_scratch_file(out, &fd);
            if (::write(fd, "half", 4) != 4) ::_exit(3);
            ::raise(sig);
            ::_exit(fs::exists(scratch) ? 4 : 5);  // not reached: the signal ends the child
        }
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ": exit " << WEXITSTATUS(status);
        EXPECT_EQ(WTERMSIG(status), sig);
        EXPECT_EQ(entries(dir), 1u) << "signal " << sig;
        EXPECT_EQ(contents(out), "the old image");
    }
}

// Committed and discarded scratch files give their places back: after 100 writes (more than the
// registry's places), a signal still removes the scratch file of the write under way.
TEST(FileIo, ScratchFilesDoneWithAreForgotten) {
    const fs::path dir = fresh_dir("rt_io_signal_many");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        for (int i = 0; i < 50; ++i) {
            std::string name = "f";  // (GCC 12 warns of "f" + std::to_string as an overflow)
            name += std::to_string(i);
            const std::string out = (dir / name).string();
            rt::commit_scratch_file(rt::write_scratch_file(out, "done"), out);
            rt::discard_scratch_file(rt::create_scratch_file(out));
        }
        rt::create_scratch_file((dir / "last").string());
        ::raise(SIGTERM);
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(entries(dir), 50u);  // f0 .. f49, and no scratch file
}

// A child process that writes a scratch file (ffmpeg encoding a video) is stopped by the signal
// before the file is removed: left running, it wrote its file again (a SIGTERM to raytrace during
// --video left the hidden .mp4). Here the child would write the file 0.3 s later.
TEST(FileIo, ASignalStopsTheChildWritingTheScratchFile) {
    const fs::path dir = fresh_dir("rt_io_signal_child");
    const std::string out = (dir / "video.mp4").string();
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const std::string scratch = rt::create_scratch_file(out);
        const pid_t writer = ::fork();
        if (writer == 0) {
            ::execl("/bin/sh", "sh", "-c", ("sleep 0.3; echo late > '" + scratch + "'").c_str(),
                    static_cast<char*>(nullptr));
            ::_exit(127);
        }
        rt::set_scratch_writer(writer);
        ::raise(SIGTERM);
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status));
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // past the child's write
    EXPECT_EQ(entries(dir), 0u);
}
