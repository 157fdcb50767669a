#include "part_file.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
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

namespace {

// A part's header, `head` (the file's first bytes, through "\ndata\n" at `end`), parsed and
// checked against the file's `size`: its blocks are those of its samples and its data is the
// size they make. Returns the part without its sums.
PartFile parse_header(std::string_view head, size_t end, uint64_t size, const std::string& path) {
    std::istringstream in(
        std::string(head.substr(std::strlen(kMagic), end + 6 - std::strlen(kMagic))));
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
    if (!fits || size != want)
        throw std::runtime_error(path + ": truncated: " + std::to_string(size) + " bytes, " +
                                 "its header announces " +
                                 (fits ? std::to_string(want) : "more than 2^64"));
    return f;
}

size_t header_end(std::string_view data, const std::string& path) {
    if (data.substr(0, std::strlen(kMagic)) != kMagic)
        throw std::runtime_error(path + ": not a part file (raytrace -o NAME.part writes them)");
    const size_t end = data.find("\ndata\n");
    if (end == std::string::npos)
        throw std::runtime_error(path + ": truncated: its header does not end");
    return end;
}

}  // namespace

PartFile read_part_header(const std::string& path) {
    if (std::string why = rt::regular_file_error(path); !why.empty()) throw std::runtime_error(why);
    std::ifstream in(path, std::ios::binary);
    std::string head;
    char buf[4096];
    while (head.find("\ndata\n") == std::string::npos && head.size() < rt::kMaxPartHeaderBytes &&
           in.read(buf, sizeof buf).gcount() > 0)
        head.append(buf, static_cast<size_t>(in.gcount()));
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    if (!in.eof() && (in.fail() || ec)) throw std::runtime_error("cannot read '" + path + "'");
    return parse_header(head, header_end(head, path), size, path);
}

PartFile read_part(const std::string& path) {
    std::string data, why;
    if (!rt::read_file(path, &data, &why)) throw std::runtime_error(why);
    const size_t end = header_end(data, path);
    PartFile f = parse_header(data, end, data.size(), path);
    rt::RenderPart& p = f.part;
    uint64_t check = 0;
    std::memcpy(&check, data.data() + data.size() - sizeof check, sizeof check);
    if (check != fnv1a(data.substr(0, data.size() - sizeof check)))
        throw std::runtime_error(path + ": corrupt: its checksum does not match its contents");
    const char* at = data.data() + end + 6;
    for (rt::RenderPart::Block& b : p.blocks) {
        for (std::vector<double>* v : {&b.sum, &b.sum_sq}) {
            v->resize(3 * p.pixels());
            std::memcpy(v->data(), at, v->size() * sizeof(double));
            at += v->size() * sizeof(double);
        }
    }
    return f;
}

void check_coverage(const std::vector<PartFile>& parts, const std::vector<std::string>& names) {
    if (parts.empty()) return;
    const int width = parts[0].header.width, height = parts[0].header.height;
    const uint32_t total = parts[0].header.spp;
    auto name = [&](size_t k) { return k < names.size() ? names[k] : "part " + std::to_string(k); };
    // The tiles' edges cut the image into cells whose pixels all lie in the same parts: each
    // cell is checked once, at its top left pixel, as merge_parts checks every pixel.
    std::vector<int> xs{0, width}, ys{0, height};
    for (const PartFile& f : parts) {
        xs.insert(xs.end(), {f.part.x0, f.part.x1});
        ys.insert(ys.end(), {f.part.y0, f.part.y1});
    }
    for (std::vector<int>* v : {&xs, &ys}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    struct Piece {
        uint32_t start;
        int level;
        size_t part;
    };
    std::vector<Piece> pieces;
    std::vector<size_t> row;  // the parts over a row of cells
    for (size_t j = 0; j + 1 < ys.size(); ++j) {
        const int y = ys[j];
        row.clear();
        for (size_t k = 0; k < parts.size(); ++k)
            if (parts[k].part.y0 <= y && y < parts[k].part.y1) row.push_back(k);
        for (size_t i = 0; i + 1 < xs.size(); ++i) {
            const int x = xs[i];
            pieces.clear();
            for (size_t k : row)
                if (parts[k].part.x0 <= x && x < parts[k].part.x1)
                    for (const rt::RenderPart::Block& b : parts[k].part.blocks)
                        pieces.push_back({b.start, b.level, k});
            std::sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) {
                return a.start < b.start || (a.start == b.start && a.part < b.part);
            });
            const std::string at = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): ";
            uint32_t next = 0;  // the first sample not yet covered
            for (size_t q = 0; q < pieces.size(); ++q) {
                const Piece& p = pieces[q];
                if (p.start > next)
                    throw std::invalid_argument(at + "samples " + std::to_string(next) + ".." +
                                                std::to_string(p.start - 1) + " are in no part (" +
                                                name(p.part) + " starts at sample " +
                                                std::to_string(p.start) + ")");
                if (p.start < next)
                    throw std::invalid_argument(at + "sample " + std::to_string(p.start) +
                                                " is in two parts (" + name(pieces[q - 1].part) +
                                                " and " + name(p.part) + ")");
                next = p.start + static_cast<uint32_t>(uint64_t{1} << p.level);
            }
            if (next != total)
                throw std::invalid_argument(at + "samples " + std::to_string(next) + ".." +
                                            std::to_string(total - 1) + " are in no part");
        }
    }
}

}  // namespace rtapp
