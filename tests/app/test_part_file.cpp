// The part files of a split render (app/common/part_file.h): what their header declares is
// checked before it sizes anything, the image against the budget (--max-pixels), the tile's data
// against the file's size.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "part_file.h"
#include "rt/util/limits.h"

namespace rtapp {
namespace {

namespace fs = std::filesystem;

// A part of one sample of a `width` x `height` image over the tile [0, tile_w) x [0, tile_h),
// with `stored` pixels of data (written as they are, whatever the tile).
PartFile part(int width, int height, int tile_w, int tile_h, size_t stored) {
    PartFile f;
    f.header.scene_hash = "0123456789abcdef";
    f.header.settings = "test";
    f.header.width = width, f.header.height = height;
    f.header.spp = 1;
    rt::RenderPart& p = f.part;
    p.x1 = tile_w, p.y1 = tile_h;
    p.first = 0, p.count = 1, p.total = 1;
    rt::RenderPart::Block& b = p.blocks.emplace_back();
    b.sum.assign(3 * stored, 0.5);
    b.sum_sq.assign(3 * stored, 0.25);
    return f;
}

// The message of reading `f` back from a file, "" when it reads.
std::string read_error(const PartFile& f) {
    // A name of this process's own: two test runs at once do not share the file.
    const fs::path path =
        fs::temp_directory_path() / ("rt_test_part_file_" + std::to_string(::getpid()) + ".part");
    write_part(path.string(), f);
    std::string error;
    try {
        read_part(path.string());
    } catch (const std::exception& e) {
        error = e.what();
    }
    fs::remove(path);
    const std::string prefix = path.string() + ": ";
    return error.rfind(prefix, 0) == 0 ? error.substr(prefix.size()) : error;
}

class PartFiles : public ::testing::Test {
    void TearDown() override { rt::set_max_image_pixels(rt::kDefaultMaxImagePixels); }
};

// A one-pixel part of a 32768 x 32768 image: merging it made the whole image (8.2 GB) first.
TEST_F(PartFiles, AnImageBeyondTheBudgetIsRefusedByItsSize) {
    EXPECT_EQ(read_error(part(32768, 32768, 1, 1, 1)),
              "its image of 32768x32768 pixels (1073741824) is larger than the budget of "
              "67108864 pixels (8192x8192); --max-pixels raises it");
    rt::set_max_image_pixels(uint64_t{1} << 30);
    EXPECT_EQ(read_error(part(32768, 32768, 1, 1, 1)), "");
}

// A tile of 2^60 pixels with no data: 48 bytes a pixel wrapped to 0 and the header's size matched
// an empty body, which std::vector was then asked to hold. The budget now stops at 2^40 pixels
// (rt::kMaxImagePixelsLimit), and a tile at that limit with no data is truncated, not allocated.
TEST_F(PartFiles, ATileLargerThanTheFileIsTruncatedWithoutOverflow) {
    rt::set_max_image_pixels(uint64_t{1} << 62);
    EXPECT_EQ(rt::max_image_pixels(), rt::kMaxImagePixelsLimit);
    EXPECT_NE(
        read_error(part(1 << 30, 1 << 30, 1 << 30, 1 << 30, 0)).find("is larger than the budget"),
        std::string::npos);
    const std::string error = read_error(part(1 << 20, 1 << 20, 1 << 20, 1 << 20, 0));
    EXPECT_NE(error.find("truncated: "), std::string::npos) << error;
}

}  // namespace
}  // namespace rtapp
