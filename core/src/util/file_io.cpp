#include "rt/util/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
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

bool read_file(const std::string& path, std::string* out, std::string* why) {
    std::string reason;
    struct stat st {};
    const int fd = open_regular(path, &st, &reason);
    out->clear();
    if (fd >= 0) {
        // The size from fstat sizes the buffer; a file that grows meanwhile is read to its end.
        out->resize(static_cast<size_t>(st.st_size));
        size_t done = 0;
        for (;;) {
            if (done == out->size()) out->resize(out->size() + 4096);
            const ssize_t n = ::read(fd, out->data() + done, out->size() - done);
            if (n > 0) {
                done += static_cast<size_t>(n);
            } else if (n == 0) {
                break;
            } else if (errno != EINTR) {
                reason = "cannot read '" + path + "': " + std::strerror(errno);
                break;
            }
        }
        out->resize(done);
        ::close(fd);
    }
    if (why) *why = reason;
    return reason.empty();
}

void write_file_atomic(const std::string& path, const std::string& data) {
    const std::string tmp = path + ".part";
    std::error_code ec;
    {
        std::ofstream f(tmp, std::ios::binary);
        f.write(data.data(), static_cast<std::streamsize>(data.size()));
        f.close();  // a failed flush on close sets failbit too
        if (!f) {
            std::filesystem::remove(tmp, ec);
            throw std::runtime_error("cannot write '" + path + "'");
        }
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + path + "'");
    }
}

}  // namespace rt
