#include "rt/image/exr.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <list>
#include <set>
#include <stdexcept>

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

// A file's bytes in memory, for OpenEXR to read (decode_exr).
class MemoryInStream : public Imf::IStream {
public:
    explicit MemoryInStream(std::string_view data) : Imf::IStream("memory"), m_data(data) {}
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

// The most values (pixels times channels) a file may hold: 16 channels of the largest image the
// budget allows (the render's RGB and its AOVs are 15 at most).
constexpr uint64_t kMaxChannelsAtBudget = 16;

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
// checked against the bytes that follow. Throws std::runtime_error.
void check_headers(std::string_view d) {
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
        // A multi-part file's headers end with an empty one.
        if (!multipart || pos >= d.size() || d[pos] == '\0') return;
    }
}

// The pixels of an open file: every channel, the data window's size. The size is checked
// against the image budget, and the channels' values against kMaxChannelsAtBudget times it,
// before the planes are allocated.
ExrImage read_exr(Imf::InputFile& file) {
    const Imath::Box2i dw = file.header().dataWindow();
    const int64_t w = int64_t{dw.max.x} - dw.min.x + 1, h = int64_t{dw.max.y} - dw.min.y + 1;
    if (w <= 0 || h <= 0) throw std::runtime_error("the data window is empty");
    const auto uw = static_cast<uint64_t>(w), uh = static_cast<uint64_t>(h);
    if (std::string e = image_size_error(uw, uh, "EXR image"); !e.empty())
        throw std::runtime_error(e);
    const Imf::ChannelList& list = file.header().channels();
    uint64_t channels = 0;
    for (auto it = list.begin(); it != list.end(); ++it) ++channels;
    if (channels * uw * uh > kMaxChannelsAtBudget * max_image_pixels())
        throw std::runtime_error("EXR image of " + std::to_string(uw) + "x" + std::to_string(uh) +
                                 " pixels in " + std::to_string(channels) +
                                 " channels holds more than " +
                                 std::to_string(kMaxChannelsAtBudget) +
                                 " channels of the image budget (--max-pixels raises it)");
    ExrImage out;
    out.width = static_cast<int>(w);
    out.height = static_cast<int>(h);
    const size_t pixels = static_cast<size_t>(w * h);
    // A list, not a vector: the slices point into the planes' words as they are added.
    std::list<Plane> planes;
    Imf::FrameBuffer frame;
    for (auto it = list.begin(); it != list.end(); ++it) {
        if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
            throw std::runtime_error(std::string("channel '") + it.name() + "' is subsampled");
        // Half and float read as float (exact), uint as uint.
        const Imf::PixelType type = it.channel().type == Imf::UINT ? Imf::UINT : Imf::FLOAT;
        planes.push_back({it.name(), it.channel().type, std::vector<uint32_t>(pixels, 0)});
        frame.insert(it.name(),
                     Imf::Slice::Make(type, planes.back().words.data(), dw, sizeof(uint32_t)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
    for (Plane& p : planes) {
        ExrChannel c;
        c.name = p.name;
        c.type = p.type == Imf::UINT    ? ExrPixel::Uint
                 : p.type == Imf::FLOAT ? ExrPixel::Float
                                        : ExrPixel::Half;
        c.values.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) {
            if (p.type == Imf::UINT) {
                c.values[i] = p.words[i];
            } else {
                float f;
                std::memcpy(&f, &p.words[i], sizeof f);
                c.values[i] = static_cast<double>(f);
            }
        }
        p.words = {};  // freed as they are converted
        out.channels.push_back(std::move(c));
    }
    return out;
}

}  // namespace

ExrImage load_exr(const std::string& path) {
    std::string data, why;
    if (!read_file(path, &data, &why)) throw std::runtime_error(why);  // regular files only
    try {
        return decode_exr(data);
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot read '" + path + "': " + e.what());
    }
}

ExrImage decode_exr(std::string_view data) {
    check_headers(data);
    MemoryInStream stream(data);
    Imf::InputFile file(stream);
    return read_exr(file);
}

}  // namespace rt
