// Whole-file reading and writing shared by the library and the programs. Writes go to a
// temporary name and are renamed, so a failed write never leaves a partial file.
#pragma once

#include <string>

namespace rt {

/// Reads a regular file whole (one allocation, one read). False when it cannot be read, with
/// the reason in *why when given (see regular_file_error). A FIFO, a device or a directory is
/// never opened for reading (a FIFO would block, /dev/zero never ends): it is refused.
bool read_file(const std::string& path, std::string* out, std::string* why = nullptr);

/// Empty when `path` names a regular file that can be opened for reading, else why not:
/// "cannot open 'x': No such file or directory", "'x' is a FIFO, not a regular file". Opens
/// without blocking, so a FIFO is never waited on. Readers that open files themselves (streams,
/// OpenEXR) call it first.
std::string regular_file_error(const std::string& path);

/// Writes `data` to path.part, checks the close, then renames it to `path`. Throws
/// std::runtime_error ("cannot write 'path'") and removes the temporary file on failure.
void write_file_atomic(const std::string& path, const std::string& data);

}  // namespace rt
