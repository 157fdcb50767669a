// The part files of a split render (app/common/part_file.h): what their header declares is
// checked before it sizes anything, the image against the budget (--max-pixels), the tile's data
// against the file's size.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <stdexcept>
#include <vector>

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
protected:
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

// A part written to a file of this process's own, removed with the fixture.
class PartHeaders : public PartFiles {
public:
    std::string write(const std::string& name, const PartFile& f) {
        const fs::path path = fs::temp_directory_path() /
                              ("rt_test_part_header_" + std::to_string(::getpid()) + "_" + name);
        write_part(path.string(), f);
        written.push_back(path);
        return path.string();
    }
    void TearDown() override {
        for (const fs::path& p : written) fs::remove(p);
        PartFiles::TearDown();
    }
    std::vector<fs::path> written;
};

// raymerge reads every part's header first: the header alone, checked as read_part checks it,
// the file's size against the data it announces, and no sums.
TEST_F(PartHeaders, AHeaderIsReadWithoutItsPixels) {
    const std::string path = write("whole.part", part(8, 6, 4, 3, 12));
    const PartFile h = read_part_header(path), f = read_part(path);
    EXPECT_EQ(h.header.width, 8);
    EXPECT_EQ(h.header.settings, f.header.settings);
    EXPECT_EQ(h.part.x1, 4);
    EXPECT_EQ(h.part.y1, 3);
    ASSERT_EQ(h.part.blocks.size(), 1u);
    EXPECT_TRUE(h.part.blocks[0].sum.empty());
    EXPECT_EQ(f.part.blocks[0].sum.size(), 36u);
    // A tile announcing more pixels than the file holds: truncated, from its size alone.
    const std::string short_path = write("short.part", part(8, 6, 4, 3, 11));
    try {
        read_part_header(short_path);
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        const std::string size = std::to_string(fs::file_size(short_path));
        EXPECT_EQ(std::string(e.what()), short_path + ": truncated: " + size +
                                             " bytes, its header announces " +
                                             std::to_string(fs::file_size(short_path) + 48));
    }
}

// The message of check_coverage over parts given as (x0, y0, x1, y1, first, count) of a
// `width` x `height` image of `spp` samples, named A, B, C...; "" when they cover it.
std::string coverage_error(int width, int height, uint32_t spp,
                           const std::vector<std::array<int, 6>>& tiles) {
    std::vector<PartFile> parts;
    std::vector<std::string> names;
    for (const auto& t : tiles) {
        PartFile f;
        f.header.width = width, f.header.height = height, f.header.spp = spp;
        rt::RenderPart& p = f.part;
        p.x0 = t[0], p.y0 = t[1], p.x1 = t[2], p.y1 = t[3];
        p.first = static_cast<uint32_t>(t[4]), p.count = static_cast<uint32_t>(t[5]);
        p.total = spp;
        for (const auto& [start, level] : rt::dyadic_blocks(p.first, p.count))
            p.blocks.push_back({start, level, {}, {}, {}});
        parts.push_back(std::move(f));
        names.push_back(std::string(1, static_cast<char>('A' + names.size())));
    }
    try {
        check_coverage(parts, names);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

// Issue 49: raymerge allocated the whole image before it found that the parts did not cover it
// (a 148 KB part of an 8192x8192 image: 5.5 GB). The coverage is checked from the tiles and
// samples alone, with the messages merge_parts gives, at the first pixel row by row.
TEST_F(PartFiles, CoverageIsCheckedFromTheHeaders) {
    EXPECT_EQ(coverage_error(61, 45, 6, {{0, 0, 30, 45, 0, 6}, {30, 0, 61, 45, 0, 6}}), "");
    EXPECT_EQ(coverage_error(61, 45, 6,
                             {{0, 0, 61, 13, 0, 3},
                              {0, 0, 61, 13, 3, 3},
                              {0, 13, 17, 45, 0, 6},
                              {17, 13, 61, 45, 0, 5},
                              {17, 13, 61, 45, 5, 1}}),
              "");
    EXPECT_EQ(coverage_error(61, 45, 6, {{0, 0, 30, 45, 0, 6}, {30, 0, 61, 20, 0, 6}}),
              "pixel (30, 20): samples 0..5 are in no part");
    EXPECT_EQ(coverage_error(61, 45, 6, {{0, 0, 61, 45, 0, 1}, {0, 0, 61, 45, 1, 3}}),
              "pixel (0, 0): samples 4..5 are in no part");
    EXPECT_EQ(coverage_error(61, 45, 6, {{0, 0, 61, 45, 0, 2}, {0, 0, 61, 45, 4, 2}}),
              "pixel (0, 0): samples 2..3 are in no part (B starts at sample 4)");
    EXPECT_EQ(coverage_error(61, 45, 6, {{0, 0, 61, 45, 0, 6}, {10, 5, 11, 6, 0, 6}}),
              "pixel (10, 5): sample 0 is in two parts (A and B)");
    // One corner of a 32768x32768 image: its pixels are never allocated, one by one or at once.
    rt::set_max_image_pixels(uint64_t{1} << 30);
    EXPECT_EQ(coverage_error(32768, 32768, 1, {{0, 0, 40, 40, 0, 1}}),
              "pixel (40, 0): samples 0..0 are in no part");
}

}  // namespace
}  // namespace rtapp
