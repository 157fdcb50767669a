// Replays files through a fuzz target without libFuzzer: `fuzz_replay_NAME FILE|DIR...`. Linked
// with each target (tests/fuzz/CMakeLists.txt), it runs the crashers and the seeds of every target
// in every build, sanitized or not.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "rt/util/file_io.h"

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv);
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const fs::path p = fs::absolute(argv[i]);  // the target changes directory
        if (fs::is_directory(p)) {
            for (const auto& e : fs::recursive_directory_iterator(p))
                // Notes beside the inputs (README.md, .gitkeep) are not inputs.
                if (e.is_regular_file() && e.path().extension() != ".md" &&
                    e.path().filename().string()[0] != '.')
                    files.push_back(e.path().string());
        } else {
            files.push_back(p.string());
        }
    }
    std::sort(files.begin(), files.end());
    LLVMFuzzerInitialize(&argc, &argv);
    for (const std::string& f : files) {
        std::string data;
        if (!rt::read_file(f, &data)) {
            std::fprintf(stderr, "fuzz_replay: cannot read %s\n", f.c_str());
            return 1;
        }
        std::fprintf(stderr, "fuzz_replay: %s\n", f.c_str());
        LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(data.data()), data.size());
    }
    std::printf("fuzz_replay: %zu files, no crash\n", files.size());
    return 0;
}
