#include "rt/image/exr.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfVersion.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "rt/util/file_io.h"
#include "rt/util/limits.h"

namespace rt {

namespace {

// The encoded file in memory: OpenEXR writes it here (seeking back for its offset table), and
// write_file_atomic() puts it on disk, so a failed write never leaves a partial file.
class MemoryStream : public Imf::OStream {
public:
    explicit MemoryStream(const std::string& name) : Imf::OStream(name.c_str()) {}
    void write(const char c[], int n) override {
        const size_t end = m_pos + static_cast<size_t>(n);
        if (end > m_data.size()) m_data.resize(end);
        std::memcpy(m_data.data() + m_pos, c, static_cast<size_t>(n));
        m_pos = end;
    }
    uint64_t tellp() override { return m_pos; }
    void seekp(uint64_t pos) override { m_pos = static_cast<size_t>(pos); }
    const std::string& data() const { return m_data; }

private:
    std::string m_data;
    size_t m_pos = 0;
};

// A file's bytes in memory, for OpenEXR to read (decode_exr); `name` is the one its messages
// give.
class MemoryInStream : public Imf::IStream {
public:
    explicit MemoryInStream(std::string_view data, const char* name = "memory")
        : Imf::IStream(name), m_data(data) {}
    bool read(char c[], int n) override {
        if (n < 0 || static_cast<size_t>(n) > m_data.size() - m_pos)
            throw std::runtime_error("the file ends early (truncated EXR)");
        std::memcpy(c, m_data.data() + m_pos, static_cast<size_t>(n));
        m_pos += static_cast<size_t>(n);
        return m_pos < m_data.size();
    }
    uint64_t tellg() override { return m_pos; }
    void seekg(uint64_t pos) override { m_pos = std::min<uint64_t>(pos, m_data.size()); }
    void clear() override {}

private:
    std::string_view m_data;
    size_t m_pos = 0;
};

// One channel's values as the file stores them, 4 bytes per value (half uses the first 2).
struct Plane {
    std::string name;
    Imf::PixelType type;
    std::vector<uint32_t> words;
};

// A value as half: finite values beyond half's range clamp to +-65504 (no new infinities).
Imath::half to_half(double v) {
    if (std::isfinite(v)) v = std::clamp(v, -static_cast<double>(HALF_MAX), double{HALF_MAX});
    return Imath::half(static_cast<float>(v));
}

uint32_t to_uint(double v) {
    if (!(v > 0)) return 0;  // NaN and negative values
    if (v >= 4294967295.0) return 4294967295u;
    return static_cast<uint32_t>(std::llround(v));
}

// `values` (every `stride`-th from `first`) packed as `type`; `rgb` turns every non-finite value
// into 0 (spec §9), otherwise only NaN.
Plane pack(const std::string& name, Imf::PixelType type, const std::vector<double>& values,
           size_t first, size_t stride, size_t count, bool rgb) {
    Plane p{name, type, std::vector<uint32_t>(count, 0)};
    for (size_t i = 0; i < count; ++i) {
        double v = values[first + i * stride];
        if (std::isnan(v) || (rgb && !std::isfinite(v))) v = 0.0;
        switch (type) {
            case Imf::HALF: {
                const uint16_t bits = to_half(v).bits();
                std::memcpy(&p.words[i], &bits, sizeof bits);
                break;
            }
            case Imf::FLOAT: {
                const float f = static_cast<float>(v);
                std::memcpy(&p.words[i], &f, sizeof f);
                break;
            }
            default:
                p.words[i] = to_uint(v);
                break;
        }
    }
    return p;
}

Imf::PixelType pixel_type(ExrPixel t, bool full_float) {
    switch (t) {
        case ExrPixel::Half:
            return full_float ? Imf::FLOAT : Imf::HALF;
        case ExrPixel::Float:
            return Imf::FLOAT;
        case ExrPixel::Uint:
            break;
    }
    return Imf::UINT;
}

}  // namespace

void save_exr(const Image& rgb, const std::vector<ExrChannel>& extra, bool full_float,
              const std::string& path) {
    if (rgb.width <= 0 || rgb.height <= 0)
        throw std::runtime_error("cannot write '" + path + "': the image is empty");
    const size_t pixels = static_cast<size_t>(rgb.width) * static_cast<size_t>(rgb.height);
    std::set<std::string> names{"R", "G", "B"};
    for (const ExrChannel& c : extra) {
        if (c.name.empty() || !names.insert(c.name).second)
            throw std::runtime_error("cannot write '" + path + "': channel name '" + c.name +
                                     "' is empty or given twice");
        if (c.values.size() != pixels)
            throw std::runtime_error("cannot write '" + path + "': channel '" + c.name + "' has " +
                                     std::to_string(c.values.size()) + " values for " +
                                     std::to_string(pixels) + " pixels");
    }
    std::vector<Plane> planes;
    const Imf::PixelType rgb_type = full_float ? Imf::FLOAT : Imf::HALF;
    const char* rgb_names[3] = {"R", "G", "B"};
    for (size_t k = 0; k < 3; ++k)
        planes.push_back(pack(rgb_names[k], rgb_type, rgb.rgb, k, 3, pixels, true));
    for (const ExrChannel& c : extra)
        planes.push_back(
            pack(c.name, pixel_type(c.type, full_float), c.values, 0, 1, pixels, false));

    MemoryStream stream(path);
    try {
        Imf::Header header(rgb.width, rgb.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        header.lineOrder() = Imf::INCREASING_Y;  // row 0 is the top row (spec §9)
        Imf::FrameBuffer frame;
        for (const Plane& p : planes) {
            header.channels().insert(p.name, Imf::Channel(p.type));
            frame.insert(
                p.name,
                Imf::Slice(p.type, reinterpret_cast<char*>(const_cast<uint32_t*>(p.words.data())),
                           sizeof(uint32_t), sizeof(uint32_t) * static_cast<size_t>(rgb.width)));
        }
        Imf::OutputFile file(stream, header);
        file.setFrameBuffer(frame);
        file.writePixels(rgb.height);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot encode '" + path + "': " + e.what());
    }
    write_file_atomic(path, stream.data());
}

namespace {

// OpenEXR 3.1 allocates an attribute's declared size before reading it (fuzz_image: a 300-byte
// file declaring a 1.8 GB string): every header's attributes are walked first, and each size
// checked against the bytes that follow. Returns where the headers end: the chunk offset tables
// follow. Throws std::runtime_error.
size_t check_headers(std::string_view d) {
    static constexpr char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (d.size() < 8 || d.substr(0, 4) != std::string_view(kMagic, 4))
        throw std::runtime_error("not an OpenEXR file");
    const bool multipart = (static_cast<uint8_t>(d[5]) & 0x10) != 0;  // version flag bit 12
    size_t pos = 8;
    auto text = [&]() {  // a null-terminated name of at most 255 bytes
        const size_t end = d.find('\0', pos);
        if (end == std::string_view::npos || end - pos > 255)
            throw std::runtime_error("truncated or bad EXR header");
        const std::string_view t = d.substr(pos, end - pos);
        pos = end + 1;
        return t;
    };
    for (;;) {
        for (std::string_view name = text(); !name.empty(); name = text()) {
            (void)text();  // the type
            if (d.size() - pos < 4) throw std::runtime_error("truncated EXR header");
            const uint32_t size = static_cast<uint32_t>(static_cast<uint8_t>(d[pos])) |
                                  static_cast<uint32_t>(static_cast<uint8_t>(d[pos + 1])) << 8 |
                                  static_cast<uint32_t>(static_cast<uint8_t>(d[pos + 2])) << 16 |
                                  static_cast<uint32_t>(static_cast<uint8_t>(d[pos + 3])) << 24;
            pos += 4;
            if (size > d.size() - pos)
                throw std::runtime_error("EXR attribute '" + std::string(name) + "' of " +
                                         std::to_string(size) + " bytes beyond the file's end");
            pos += size;
        }
        if (!multipart) return pos;
        // A multi-part file's headers end with an empty one.
        if (pos >= d.size()) throw std::runtime_error("truncated EXR header");
        if (d[pos] == '\0') return pos + 1;
    }
}

// Little-endian integers at `pos` (the caller checks that they are inside `d`).
uint64_t read_le(std::string_view d, size_t pos, size_t bytes) {
    uint64_t v = 0;
    for (size_t i = 0; i < bytes; ++i) v |= uint64_t{static_cast<uint8_t>(d[pos + i])} << (8 * i);
    return v;
}

// Scan lines per chunk of each compression (OpenEXR's numLinesInBuffer, not in its headers).
int64_t lines_per_chunk(Imf::Compression c) {
    switch (c) {
        case Imf::NO_COMPRESSION:
        case Imf::RLE_COMPRESSION:
        case Imf::ZIPS_COMPRESSION:
            return 1;
        case Imf::ZIP_COMPRESSION:
        case Imf::PXR24_COMPRESSION:
            return 16;
        case Imf::PIZ_COMPRESSION:
        case Imf::B44_COMPRESSION:
        case Imf::B44A_COMPRESSION:
        case Imf::DWAA_COMPRESSION:
            return 32;
        case Imf::DWAB_COMPRESSION:
            return 256;
        default:
            break;
    }
    throw std::runtime_error("unknown EXR compression " + std::to_string(static_cast<int>(c)));
}

uint64_t product(uint64_t a, uint64_t b) {  // saturates: a count beyond any file
    return a != 0 && b > UINT64_MAX / a ? UINT64_MAX : a * b;
}

uint64_t sum(uint64_t a, uint64_t b) { return b > UINT64_MAX - a ? UINT64_MAX : a + b; }

// Tiles along one axis of a tiled part, over its levels (OpenEXR's precalculateTileInfo).
std::vector<uint64_t> tiles_per_level(int64_t size, int64_t tile, int levels,
                                      Imf::LevelRoundingMode round) {
    std::vector<uint64_t> n;
    for (int l = 0; l < levels; ++l) {
        int64_t s = size >> l;
        if (round == Imf::ROUND_UP && (s << l) < size) ++s;
        s = std::max<int64_t>(s, 1);
        n.push_back(static_cast<uint64_t>((s + tile - 1) / tile));
    }
    return n;
}

int level_count(int64_t size, Imf::LevelRoundingMode round) {
    int floor_log = 0;
    bool exact = true;
    for (int64_t s = size; s > 1; s >>= 1) {
        exact = exact && (s & 1) == 0;
        ++floor_log;
    }
    return floor_log + (round == Imf::ROUND_UP && !exact ? 1 : 0) + 1;
}

// A part's chunks as its header declares them: scan-line blocks or tiles over every level.
uint64_t chunk_count(const Imf::Header& h, bool tiled) {
    const Imath::Box2i dw = h.dataWindow();
    const int64_t w = int64_t{dw.max.x} - dw.min.x + 1, ht = int64_t{dw.max.y} - dw.min.y + 1;
    if (!tiled) {
        const int64_t n = lines_per_chunk(h.compression());
        return static_cast<uint64_t>((ht + n - 1) / n);
    }
    const Imf::TileDescription& t = h.tileDescription();
    const int64_t tx = std::max<int64_t>(t.xSize, 1), ty = std::max<int64_t>(t.ySize, 1);
    switch (t.mode) {
        case Imf::ONE_LEVEL:
            return product(tiles_per_level(w, tx, 1, t.roundingMode)[0],
                           tiles_per_level(ht, ty, 1, t.roundingMode)[0]);
        case Imf::MIPMAP_LEVELS: {
            const int levels = level_count(std::max(w, ht), t.roundingMode);
            const auto xs = tiles_per_level(w, tx, levels, t.roundingMode);
            const auto ys = tiles_per_level(ht, ty, levels, t.roundingMode);
            uint64_t n = 0;
            for (int l = 0; l < levels; ++l) n = sum(n, product(xs[l], ys[l]));
            return n;
        }
        case Imf::RIPMAP_LEVELS: {
            uint64_t nx = 0, ny = 0;
            for (uint64_t v :
                 tiles_per_level(w, tx, level_count(w, t.roundingMode), t.roundingMode))
                nx = sum(nx, v);
            for (uint64_t v :
                 tiles_per_level(ht, ty, level_count(ht, t.roundingMode), t.roundingMode))
                ny = sum(ny, v);
            return product(nx, ny);
        }
        default:
            break;
    }
    throw std::runtime_error("unknown EXR tile level mode");
}

struct ChunkPart {
    uint64_t chunks;
    size_t prefix;  // the bytes of a chunk's own header
    bool deep;
};

// check_chunks()'s first half: every part's header in turn, its chunks (which the offset tables
// must have room for in the file) and the size of their own headers; *total_out: the chunks of all.
std::vector<ChunkPart> chunk_parts(std::string_view d, size_t tables, uint64_t* total_out) {
    MemoryInStream stream(d);
    stream.seekg(4);
    const int version = static_cast<int>(read_le(d, 4, 4));
    stream.seekg(8);
    const bool multipart = Imf::isMultiPart(version);
    std::vector<ChunkPart> parts;
    uint64_t total = 0;
    for (;;) {
        Imf::Header h;
        int read_version = version;  // readFrom may change it
        h.readFrom(stream, read_version);
        const std::string type = h.hasType()             ? h.type()
                                 : Imf::isTiled(version) ? Imf::TILEDIMAGE
                                                         : Imf::SCANLINEIMAGE;
        const bool tiled = Imf::isTiled(type), deep = Imf::isDeepData(type);
        if (!tiled && type != Imf::SCANLINEIMAGE && type != Imf::DEEPSCANLINE)
            throw std::runtime_error("unknown EXR part type '" + type + "'");
        h.sanityCheck(tiled);
        const uint64_t n = chunk_count(h, tiled);
        const uint64_t room = (d.size() - tables) / 8;
        if (h.hasChunkCount() && static_cast<uint64_t>(h.chunkCount()) != n)
            throw std::runtime_error("the EXR header's chunk count " +
                                     std::to_string(h.chunkCount()) + " is not the " +
                                     std::to_string(n) + " chunks of its data window");
        // Part number, coordinates (y, or 4 for a tile), then the sizes: the packed data's, or
        // a deep chunk's sample table, packed and unpacked data (8 bytes each).
        parts.push_back({n, (multipart ? 4u : 0u) + (tiled ? 16u : 4u) + (deep ? 24u : 4u), deep});
        if (n > room || total + n > room) {
            const Imath::Box2i dw = h.dataWindow();
            throw std::runtime_error(
                "the EXR header's " + std::to_string(int64_t{dw.max.x} - dw.min.x + 1) + "x" +
                std::to_string(int64_t{dw.max.y} - dw.min.y + 1) + " pixels are " +
                std::to_string(n) + " chunks, whose offset table alone is larger than the " +
                std::to_string(d.size()) + "-byte file (truncated or damaged)");
        }
        total += n;
        const uint64_t next = stream.tellg();
        if (!multipart || next >= d.size() || d[static_cast<size_t>(next)] == '\0') break;
    }
    *total_out = total;
    return parts;
}

// OpenEXR trusts a file's chunk offset tables: it allocates them at the size its headers imply
// (8 bytes a chunk), and a chunk missing from the file is found only when its pixels are read,
// after the caller has allocated the image. So before OpenEXR opens the file, every part's table
// is checked against the file's bytes: the tables fit in the file, every chunk (its offset, its
// own header and the data size it declares) lies inside the file after the tables, and no two
// chunks overlap. A file that passes holds every chunk its headers declare.
void check_chunks(std::string_view d, size_t tables) {
    const bool multipart = Imf::isMultiPart(static_cast<int>(read_le(d, 4, 4)));
    uint64_t total = 0;
    const std::vector<ChunkPart> parts = chunk_parts(d, tables, &total);
    const size_t chunks_start = tables + static_cast<size_t>(total) * 8;
    std::vector<std::pair<uint64_t, uint64_t>> spans;  // [start, end) of every chunk
    spans.reserve(static_cast<size_t>(total));
    size_t entry = tables;
    for (size_t p = 0; p < parts.size(); ++p) {
        for (uint64_t i = 0; i < parts[p].chunks; ++i, entry += 8) {
            const uint64_t at = read_le(d, entry, 8);
            auto beyond = [&]() {
                return std::runtime_error(
                    "EXR chunk " + std::to_string(i) +
                    (parts.size() > 1 ? " of part " + std::to_string(p) : "") + " points at byte " +
                    std::to_string(at) + ", outside the chunks' bytes " +
                    std::to_string(chunks_start) + " to " + std::to_string(d.size()) +
                    " (a damaged offset table or a truncated file)");
            };
            if (at < chunks_start || at > d.size() || d.size() - at < parts[p].prefix)
                throw beyond();
            if (multipart && read_le(d, at, 4) != p)
                throw std::runtime_error("EXR chunk " + std::to_string(i) + " of part " +
                                         std::to_string(p) + " names another part");
            const size_t sizes = at + parts[p].prefix - (parts[p].deep ? 24 : 4);
            uint64_t data = 0;
            if (parts[p].deep) {
                const uint64_t table = read_le(d, sizes, 8), packed = read_le(d, sizes + 8, 8);
                data = table > d.size() || packed > d.size() ? d.size() : table + packed;
            } else {
                data = static_cast<uint32_t>(read_le(d, sizes, 4));
                if (data > 0x7fffffff) throw beyond();  // a negative size
            }
            if (data > d.size() - at - parts[p].prefix) throw beyond();
            spans.emplace_back(at, at + parts[p].prefix + data);
        }
    }
    std::sort(spans.begin(), spans.end());
    for (size_t i = 1; i < spans.size(); ++i)
        if (spans[i].first < spans[i - 1].second)
            throw std::runtime_error("EXR chunks overlap at byte " +
                                     std::to_string(spans[i].first) + " (a damaged offset table)");
}

// Pixels are read in bands of whole chunks of about this many values: the buffers follow the
// chunks that decode, not the size the header claims.
constexpr uint64_t kBandValues = uint64_t{1} << 20;

// Reads the channels `names` of an open file, band by band from the top, and hands each band to
// `store(channel, first pixel, words, count)` (4 bytes a value: float, or uint for Uint
// channels). The caller's image grows as the bands arrive (see grow()).
template <class Store>
void read_bands(Imf::InputFile& file, const std::vector<std::string>& names,
                const std::vector<Imf::PixelType>& types, Store store) {
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    const int64_t w = int64_t{dw.max.x} - dw.min.x + 1, ht = int64_t{dw.max.y} - dw.min.y + 1;
    const bool tiled = h.hasType() ? Imf::isTiled(h.type()) : Imf::isTiled(file.version());
    // Whole chunks, at most the image (checked against the budget): no product overflows.
    const int64_t block = std::min(ht, tiled && h.hasTileDescription()
                                           ? std::max<int64_t>(h.tileDescription().ySize, 1)
                                           : lines_per_chunk(h.compression()));
    const auto nch = static_cast<int64_t>(std::max<size_t>(names.size(), 1));
    const int64_t rows =
        block * std::max<int64_t>(1, static_cast<int64_t>(kBandValues) / (w * block * nch));
    std::vector<uint32_t> band;
    for (int64_t y = 0; y < ht; y += rows) {
        const int64_t n = std::min(rows, ht - y);
        const auto count = static_cast<size_t>(w * n);
        band.assign(count * names.size(), 0);
        const Imath::Box2i box(Imath::V2i(dw.min.x, static_cast<int>(dw.min.y + y)),
                               Imath::V2i(dw.max.x, static_cast<int>(dw.min.y + y + n - 1)));
        Imf::FrameBuffer frame;
        for (size_t c = 0; c < names.size(); ++c)
            frame.insert(names[c], Imf::Slice::Make(types[c], band.data() + c * count, box,
                                                    sizeof(uint32_t)));
        file.setFrameBuffer(frame);
        file.readPixels(box.min.y, box.max.y);
        for (size_t c = 0; c < names.size(); ++c)
            store(c, static_cast<size_t>(y * w), band.data() + c * count, count);
    }
}

// Makes room for `size` values in `v`, at least doubling its capacity up to `total`: an image
// grows with the bands that decode (a file whose chunks after the first are damaged costs
// twice what was read, never the size its header claims), and is allocated about once and a
// half in all.
void grow(std::vector<double>& v, size_t size, size_t total) {
    if (v.capacity() < size) v.reserve(std::min(total, std::max(size, 2 * v.capacity())));
    v.resize(size);
}

double value(uint32_t word, Imf::PixelType type) {
    if (type == Imf::UINT) return word;
    float f;
    std::memcpy(&f, &word, sizeof f);
    return static_cast<double>(f);
}

// The file's header checked, its data window's size against the image budget and `channels`
// values a pixel against kMaxExrChannelsAtBudget times it. Returns the width and height.
std::pair<int, int> checked_size(const Imf::Header& h, uint64_t channels) {
    const Imath::Box2i dw = h.dataWindow();
    const int64_t w = int64_t{dw.max.x} - dw.min.x + 1, ht = int64_t{dw.max.y} - dw.min.y + 1;
    if (w <= 0 || ht <= 0) throw std::runtime_error("the data window is empty");
    const auto uw = static_cast<uint64_t>(w), uh = static_cast<uint64_t>(ht);
    if (std::string e = image_size_error(uw, uh, "EXR image"); !e.empty())
        throw std::runtime_error(e);
    if (channels * uw * uh > kMaxExrChannelsAtBudget * max_image_pixels())
        throw std::runtime_error("EXR image of " + std::to_string(uw) + "x" + std::to_string(uh) +
                                 " pixels in " + std::to_string(channels) +
                                 " channels holds more than " +
                                 std::to_string(kMaxExrChannelsAtBudget) +
                                 " channels of the image budget (--max-pixels raises it)");
    return {static_cast<int>(w), static_cast<int>(ht)};
}

void check_sampling(const char* name, const Imf::Channel& c) {
    if (c.xSampling != 1 || c.ySampling != 1)
        throw std::runtime_error(std::string("channel '") + name + "' is subsampled");
}

// Opens the file's bytes in OpenEXR once its headers and chunk tables are checked.
template <class Read>
auto with_file(std::string_view data, const std::string& name, Read read) {
    check_chunks(data, check_headers(data));
    MemoryInStream stream(data, name.c_str());
    Imf::InputFile file(stream);
    return read(file);
}

// Every channel of an open file.
ExrImage read_exr(Imf::InputFile& file) {
    const Imf::ChannelList& list = file.header().channels();
    std::vector<std::string> names;
    std::vector<Imf::PixelType> types;
    ExrImage out;
    for (auto it = list.begin(); it != list.end(); ++it) {
        check_sampling(it.name(), it.channel());
        names.emplace_back(it.name());
        // Half and float read as float (exact), uint as uint.
        types.push_back(it.channel().type == Imf::UINT ? Imf::UINT : Imf::FLOAT);
        ExrChannel c;
        c.name = it.name();
        c.type = it.channel().type == Imf::UINT    ? ExrPixel::Uint
                 : it.channel().type == Imf::FLOAT ? ExrPixel::Float
                                                   : ExrPixel::Half;
        out.channels.push_back(std::move(c));
    }
    std::tie(out.width, out.height) = checked_size(file.header(), names.size());
    const size_t pixels = static_cast<size_t>(out.width) * static_cast<size_t>(out.height);
    read_bands(file, names, types,
               [&](size_t c, size_t first, const uint32_t* words, size_t count) {
                   std::vector<double>& v = out.channels[c].values;
                   grow(v, first + count, pixels);
                   for (size_t i = 0; i < count; ++i) v[first + i] = value(words[i], types[c]);
               });
    return out;
}

// R, G and B of an open file; its other channels are not read.
Image read_exr_rgb(Imf::InputFile& file) {
    const Imf::ChannelList& list = file.header().channels();
    const std::vector<std::string> names{"R", "G", "B"};
    std::vector<Imf::PixelType> types;
    for (const std::string& n : names) {
        const Imf::Channel* c = list.findChannel(n);
        if (!c) throw std::runtime_error("the EXR image has no channel " + n);
        check_sampling(n.c_str(), *c);
        types.push_back(c->type == Imf::UINT ? Imf::UINT : Imf::FLOAT);  // as read_exr
    }
    Image out;
    std::tie(out.width, out.height) = checked_size(file.header(), names.size());
    const size_t values = static_cast<size_t>(out.width) * static_cast<size_t>(out.height) * 3;
    read_bands(file, names, types,
               [&](size_t c, size_t first, const uint32_t* words, size_t count) {
                   grow(out.rgb, std::max(out.rgb.size(), (first + count) * 3), values);
                   for (size_t i = 0; i < count; ++i)
                       out.rgb[(first + i) * 3 + c] = value(words[i], types[c]);
               });
    return out;
}

template <class Read>
auto load(const std::string& path, Read read) {
    std::string data, why;
    if (!read_file(path, &data, &why)) throw std::runtime_error(why);  // regular files only
    try {
        return with_file(data, path, read);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot read '" + path + "': " + e.what());
    }
}

}  // namespace

ExrImage load_exr(const std::string& path) { return load(path, read_exr); }

ExrImage decode_exr(std::string_view data) { return with_file(data, "memory", read_exr); }

Image load_exr_rgb(const std::string& path) { return load(path, read_exr_rgb); }

Image decode_exr_rgb(std::string_view data) { return with_file(data, "memory", read_exr_rgb); }

}  // namespace rt
