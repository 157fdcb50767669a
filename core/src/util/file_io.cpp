#include "rt/util/file_io.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rt {

bool read_file(const std::string& path, std::string* out) {
    std::error_code ec;
    std::ifstream f(path, std::ios::binary | std::ios::ate);
    if (!f || !std::filesystem::is_regular_file(path, ec)) return false;
    const std::streamoff size = f.tellg();
    out->clear();
    if (size > 0) {
        out->resize(static_cast<size_t>(size));
        f.seekg(0);
        f.read(out->data(), size);
    }
    return static_cast<bool>(f) || size == 0;
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
