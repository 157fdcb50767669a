#include "part_file.h"

#include <bit>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "rt/util/file_io.h"
#include "rt/util/limits.h"

namespace rtapp {

static_assert(std::endian::native == std::endian::little, "part files hold little-endian doubles");

uint64_t fnv1a(const std::string& data, uint64_t hash) {
    for (const char c : data) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 0x100000001b3ull;
    }
    return hash;
}

namespace {

constexpr const char* kMagic = "RTPART 1\n";

std::string hex(uint64_t v) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

void append_doubles(std::string& out, const std::vector<double>& v) {
    if (v.empty()) return;  // its data() may be null, which memcpy must not be given
    const size_t at = out.size();
    out.resize(at + v.size() * sizeof(double));
    std::memcpy(out.data() + at, v.data(), v.size() * sizeof(double));
}

// One header line "KEY VALUES...", its values read by the caller from the returned stream.
std::istringstream line(std::istringstream& in, const std::string& key, const std::string& path) {
    std::string text;
    if (!std::getline(in, text))
        throw std::runtime_error(path + ": truncated: no '" + key + "' line");
    if (text.rfind(key + " ", 0) != 0 && text != key)
        throw std::runtime_error(path + ": bad header: expected '" + key + " ...', got '" +
                                 text.substr(0, 60) + "'");
    return std::istringstream(text.substr(std::min(text.size(), key.size() + 1)));
}

template <class... T>
void values(std::istringstream ls, const std::string& key, const std::string& path, T&... out) {
    if (!(ls >> ... >> out))
        throw std::runtime_error(path + ": bad header: the '" + key + "' line");
}

}  // namespace

std::string scene_hash(const rt::SceneDesc& desc) {
    uint64_t h = fnv1a("");
    auto add = [&](const std::string& path) {
        std::string text;
        h = fnv1a(path.substr(path.find_last_of('/') + 1) + '\n', h);  // the name, not where
        h = fnv1a(rt::read_file(path, &text) ? text : std::string("(unreadable)"), h);
    };
    for (const rt::FileDesc& f : desc.files) {
        add(f.path);
        for (const std::string& k : f.key_files) add(k);
        for (const rt::TextureDesc& t : f.textures) add(t.path);
    }
    return hex(h);
}

void write_part(const std::string& path, const PartFile& f) {
    const rt::RenderPart& p = f.part;
    std::ostringstream h;
    h << kMagic << "scene " << f.header.scene_hash << "\nsettings " << f.header.settings
      << "\nimage " << f.header.width << " " << f.header.height << "\nspp " << f.header.spp
      << "\ntile " << p.x0 << " " << p.y0 << " " << p.x1 << " " << p.y1 << "\nsamples " << p.first
      << " " << p.count << "\nrays " << p.rays.camera << " " << p.rays.shadow << " "
      << p.rays.reflected << " " << p.rays.refracted << "\nblocks " << p.blocks.size() << "\n";
    for (const rt::RenderPart::Block& b : p.blocks)
        h << "block " << b.start << " " << b.level << "\n";
    h << "data\n";
    std::string out = h.str();
    for (const rt::RenderPart::Block& b : p.blocks) {
        append_doubles(out, b.sum);
        append_doubles(out, b.sum_sq);
    }
    const uint64_t check = fnv1a(out);
    out.append(reinterpret_cast<const char*>(&check), sizeof check);
    try {
        rt::write_file_atomic(path, out);
    } catch (const std::exception&) {
        throw std::runtime_error("cannot write '" + path + "'");
    }
}

PartFile read_part(const std::string& path) {
    std::string data, why;
    if (!rt::read_file(path, &data, &why)) throw std::runtime_error(why);
    if (data.rfind(kMagic, 0) != 0)
        throw std::runtime_error(path + ": not a part file (raytrace -o NAME.part writes them)");
    const size_t end = data.find("\ndata\n");
    if (end == std::string::npos)
        throw std::runtime_error(path + ": truncated: its header does not end");
    std::istringstream in(data.substr(std::strlen(kMagic), end + 6 - std::strlen(kMagic)));
    PartFile f;
    rt::RenderPart& p = f.part;
    values(line(in, "scene", path), "scene", path, f.header.scene_hash);
    {
        std::istringstream ls = line(in, "settings", path);
        f.header.settings = ls.str();
    }
    values(line(in, "image", path), "image", path, f.header.width, f.header.height);
    values(line(in, "spp", path), "spp", path, f.header.spp);
    values(line(in, "tile", path), "tile", path, p.x0, p.y0, p.x1, p.y1);
    values(line(in, "samples", path), "samples", path, p.first, p.count);
    values(line(in, "rays", path), "rays", path, p.rays.camera, p.rays.shadow, p.rays.reflected,
           p.rays.refracted);
    size_t blocks = 0;
    values(line(in, "blocks", path), "blocks", path, blocks);
    p.total = f.header.spp;
    if (f.header.width <= 0 || f.header.height <= 0 || p.x0 < 0 || p.y0 < 0 ||
        p.x1 > f.header.width || p.y1 > f.header.height || p.x0 >= p.x1 || p.y0 >= p.y1)
        throw std::runtime_error(path + ": bad header: its tile is not inside its image");
    // Merging makes the whole image: refuse one beyond the budget before anything is allocated.
    if (const std::string e =
            rt::image_size_error(static_cast<uint64_t>(f.header.width),
                                 static_cast<uint64_t>(f.header.height), "its image");
        !e.empty())
        throw std::runtime_error(path + ": " + e);
    if (blocks == 0 || blocks > 64)
        throw std::runtime_error(path + ": bad header: " + std::to_string(blocks) + " blocks");
    // Its blocks must be the dyadic blocks of its samples.
    if (p.count == 0 || p.first >= p.total || p.count > p.total - p.first)
        throw std::runtime_error(path + ": bad header: its samples do not match its blocks");
    const std::vector<std::pair<uint32_t, int>> expected = rt::dyadic_blocks(p.first, p.count);
    if (expected.size() != blocks)
        throw std::runtime_error(path + ": bad header: its samples do not match its blocks");
    p.blocks.resize(blocks);
    for (size_t b = 0; b < blocks; ++b) {
        values(line(in, "block", path), "block", path, p.blocks[b].start, p.blocks[b].level);
        if (p.blocks[b].start != expected[b].first || p.blocks[b].level != expected[b].second)
            throw std::runtime_error(path + ": bad header: block " + std::to_string(b) +
                                     " is not a block of its samples");
    }
    // The size its header announces: 6 doubles per pixel and block after the header, then the
    // checksum. A tile of up to 2^62 pixels could wrap that product: compared by division first.
    const size_t body = end + 6, pixel_bytes = 6 * sizeof(double) * blocks;
    const bool fits = p.pixels() <= (SIZE_MAX - body - sizeof(uint64_t)) / pixel_bytes;
    const size_t want = fits ? body + p.pixels() * pixel_bytes + sizeof(uint64_t) : 0;
    if (!fits || data.size() != want)
        throw std::runtime_error(path + ": truncated: " + std::to_string(data.size()) + " bytes, " +
                                 "its header announces " +
                                 (fits ? std::to_string(want) : "more than 2^64"));
    uint64_t check = 0;
    std::memcpy(&check, data.data() + data.size() - sizeof check, sizeof check);
    if (check != fnv1a(data.substr(0, data.size() - sizeof check)))
        throw std::runtime_error(path + ": corrupt: its checksum does not match its contents");
    const char* at = data.data() + body;
    for (rt::RenderPart::Block& b : p.blocks) {
        for (std::vector<double>* v : {&b.sum, &b.sum_sq}) {
            v->resize(3 * p.pixels());
            std::memcpy(v->data(), at, v->size() * sizeof(double));
            at += v->size() * sizeof(double);
        }
    }
    return f;
}

}  // namespace rtapp
