// libFuzzer target: bytes -> a part file (app/common/part_file.h, read_part: the header lines,
// the blocks, the data and the checksum; read_part_header and check_coverage, raymerge's checks
// from the header alone). Any input must end in a PartFile or a
// std::runtime_error: a crash, a sanitizer report, a hang or any other exception is a bug.
//
// The checksum (FNV-1a 64 of every byte before its last 8) would turn nearly every mutation away
// at the end: an input whose last 8 bytes are not its checksum gets its checksum appended, so the
// mutations reach the header checks and the data (the seeds in tests/fuzz/corpus/part are parts
// written by raytrace --tile and --samples, without their checksums), while an input ending in
// its right checksum is read as it is.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "fuzz_util.h"
#include "part_file.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)rt_fuzz::work_dir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, size_t size) {
    std::string data(reinterpret_cast<const char*>(bytes), size);
    uint64_t check = 0;
    if (size >= sizeof check) std::memcpy(&check, data.data() + size - sizeof check, sizeof check);
    if (size < sizeof check || check != rtapp::fnv1a(data.substr(0, size - sizeof check))) {
        check = rtapp::fnv1a(data);
        data.append(reinterpret_cast<const char*>(&check), sizeof check);
    }
    const std::string path = rt_fuzz::write_file("fuzz.part", data);
    try {
        const rtapp::PartFile part = rtapp::read_part(path);
        (void)part;
    } catch (const std::runtime_error&) {
        // The expected way for bad input to end.
    }
    // raymerge's first step: the header alone, then the coverage from it (an image the header
    // claims is never allocated).
    try {
        const rtapp::PartFile header = rtapp::read_part_header(path);
        rtapp::check_coverage({header}, {path});
    } catch (const std::runtime_error&) {
    } catch (const std::invalid_argument&) {  // the coverage's refusal
    }
    return 0;
}
