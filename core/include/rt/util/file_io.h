// Whole-file reading and writing shared by the library and the programs. Writes go to a
// temporary name and are renamed, so a failed write never leaves a partial file.
#pragma once

#include <string>

namespace rt {

/// Reads a regular file whole (one allocation, one read). False when it cannot be read.
bool read_file(const std::string& path, std::string* out);

/// Writes `data` to path.part, checks the close, then renames it to `path`. Throws
/// std::runtime_error ("cannot write 'path'") and removes the temporary file on failure.
void write_file_atomic(const std::string& path, const std::string& data);

}  // namespace rt
