// raymerge: the parts of a split render (raytrace -o NAME.part) merged into the image the whole
// render gives, bit for bit. Every part is checked first (its file, its scene and settings, the
// coverage of every pixel by exactly the samples 0 .. N-1, from the headers, before any pixel is
// read or the image allocated); nothing is written until all pass.
// Exit status: 0 success, 1 a part refused or the output not written, 2 usage error.

// GCC 12 at -O1 sees CLI11's split() move a string it cannot prove non-null (it is never null).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CLI/CLI.hpp>
#pragma GCC diagnostic pop
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli.h"
#include "part_file.h"
#include "raytrace/output.h"
#include "render_options.h"
#include "rt/render/render.h"

namespace {

// The first header field where `b` differs from `a`, or "".
std::string difference(const rtapp::PartFile& a, const rtapp::PartFile& b) {
    if (a.header.scene_hash != b.header.scene_hash)
        return "is of another scene (its files hash to " + b.header.scene_hash + ", not " +
               a.header.scene_hash + ")";
    if (a.header.width != b.header.width || a.header.height != b.header.height)
        return "is of another image size (" + std::to_string(b.header.width) + "x" +
               std::to_string(b.header.height) + ")";
    if (a.header.spp != b.header.spp)
        return "is of a render of " + std::to_string(b.header.spp) + " samples per pixel, not " +
               std::to_string(a.header.spp);
    if (a.header.settings != b.header.settings)
        return "was rendered with other settings ('" + b.header.settings + "', not '" +
               a.header.settings + "')";
    return "";
}

// The same header, tile and samples: a part read whole is the one whose header was checked.
bool same_part(const rtapp::PartFile& a, const rtapp::PartFile& b) {
    const rt::RenderPart &p = a.part, &q = b.part;
    return difference(a, b).empty() && p.x0 == q.x0 && p.y0 == q.y0 && p.x1 == q.x1 &&
           p.y1 == q.y1 && p.first == q.first && p.count == q.count;
}

int merge(const std::string& out, const std::vector<std::string>& paths, bool quiet) {
    if (!raytrace::probe_outputs({out})) return 1;
    // Every part's header first, its file's size checked against it, and the coverage of the
    // image from the headers alone: parts that do not make the image are refused before a pixel
    // is read or the image allocated (a 148 KB part of an 8192x8192 image allocated 5.5 GB
    // before its coverage error).
    std::vector<rtapp::PartFile> parts;
    try {
        for (const std::string& p : paths) parts.push_back(rtapp::read_part_header(p));
    } catch (const std::exception& e) {
        std::cerr << "raymerge: error: " << rtapp::error_text(e, "reading the parts") << "\n";
        return 1;
    }
    for (size_t i = 1; i < parts.size(); ++i) {
        const std::string d = difference(parts[0], parts[i]);
        if (d.empty()) continue;
        std::cerr << "raymerge: error: " << paths[i] << " " << d << " than " << paths[0] << "\n";
        return 1;
    }
    try {
        rtapp::check_coverage(parts, paths);
    } catch (const std::invalid_argument& e) {
        std::cerr << "raymerge: error: the parts do not cover the image once: " << e.what() << "\n";
        return 1;
    }
    try {
        for (size_t i = 0; i < parts.size(); ++i) {
            rtapp::PartFile whole = rtapp::read_part(paths[i]);
            if (!same_part(parts[i], whole))
                throw std::runtime_error(paths[i] + " changed while the parts were read");
            parts[i] = std::move(whole);
        }
    } catch (const std::exception& e) {
        std::cerr << "raymerge: error: " << rtapp::error_text(e, "reading the parts") << "\n";
        return 1;
    }
    std::vector<const rt::RenderPart*> ptrs;
    for (const rtapp::PartFile& p : parts) ptrs.push_back(&p.part);
    const rtapp::PartHeader& h = parts[0].header;
    try {
        const rt::RenderState state = rt::merge_parts(ptrs, h.width, h.height, h.spp, paths);
        raytrace::write_outputs(state.image(), out, {}, "raymerge");
    } catch (const std::invalid_argument& e) {
        std::cerr << "raymerge: error: the parts do not cover the image once: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "raymerge: error: " << rtapp::error_text(e, "merging the parts") << "\n";
        return 1;
    }
    if (!quiet)
        std::printf("merged    %zu part%s into %s (%dx%d, %u spp)\n", parts.size(),
                    parts.size() == 1 ? "" : "s", out.c_str(), h.width, h.height, h.spp);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Merges the parts of a split render (raytrace -o NAME.part) into its image."};
    rtapp::setup_cli(app, "raymerge");
    std::string out;
    std::vector<std::string> parts;
    bool quiet = false;
    uint64_t max_pixels = rt::kDefaultMaxImagePixels;
    app.add_option("-o,--output", out, "the image: .png .bmp .ppm (8-bit) or .pfm (float)")
        ->type_name("FILE")
        ->required();
    app.add_option("parts", parts, "the part files")->type_name("PART")->required();
    app.add_flag("-q,--quiet", quiet, "print errors only");
    rtapp::add_max_pixels_option(app, max_pixels, "the image the parts make");
    app.footer(
        "exit status: 0 success, 1 a part refused or the output not written, 2 usage error.");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }
    if (rt::image_format_from_path(out) == rt::ImageFormat::Unknown) {
        std::cerr << "raymerge: unknown output format '" << out
                  << "' (use .png, .bmp, .ppm or .pfm)\n";
        return 2;
    }
    try {
        rtapp::check_max_pixels(max_pixels);
    } catch (const rtapp::UsageError& e) {
        std::cerr << "raymerge: " << e.what() << "\n";
        return 2;
    }
    rt::set_max_image_pixels(max_pixels);  // parts of a larger image are refused as they are read
    return merge(out, parts, quiet);
}
