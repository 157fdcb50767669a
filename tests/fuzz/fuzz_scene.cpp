// libFuzzer target: scene text -> parse_scene_string -> compile_scene -> animate() at a few
// times, and the text with its materials written back in place (replace_materials). Any input must
// end in a SceneError or a compiled scene: a crash, a sanitizer report, a hang or any other
// exception is a bug. An input holding a line "#@key" is two files: the text before it is the
// scene, the text after it the key file fuzz.key (which the scene may name), so the key grammar and
// the joint values are fuzzed too; a first line "#@v0", "#@v1" or "#@v3" forces that dialect
// (forced_dialect), so any text goes through each parser, the V3 one among them (the seeds of
// tests/fuzz/corpus/scene hold some of each). Built as `fuzz_scene` (clang, -fsanitize=fuzzer) and
// as `fuzz_replay` (any compiler, replays files: the crasher regression corpus in
// tests/fuzz/crashers). The parse with its mesh runs cut into pieces of one directive on three
// threads must give what the serial parse gives, field for field, warnings and errors alike
// (tests/parse_both_ways.h); a difference aborts. Each compiled scene's ray tree of one pixel
// (--inspect at 4x4, depth 8) must be strict UTF-8 JSON (tests/json_check.h), however the
// scene's names are spelled, with no more rays than the tree's limit.
//
// Includes, textures and key files cannot escape: the harness works in a private temporary
// directory holding a few fixture files (inc.ray, inc0.ray, the V3 inc3.ray, loop.ray, tex.ppm,
// anim.key), and every '/' that could end up in a path is replaced by '_' before parsing, so only
// names in that directory resolve. A texture that does not resolve (such as tex.bmp, the course's
// name) stands in as a checker (--missing-textures checker), so such scenes get past loading.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "../json_check.h"
#include "../parse_both_ways.h"
#include "fuzz_util.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/format/writer.h"
#include "rt/render/inspect.h"
#include "rt/scene/scene_time.h"

namespace {

using rt_fuzz::write_file;

void setup() {
    static bool done = false;
    if (done) return;
    done = true;
    write_file("inc.ray",
               "#material 0 0 0 .1 .1 .1 .5 .5 .5 .2 .2 .2 10 0 0 0 1 0 !m!\n"
               "#texture tex.ppm\n#vertex 0 0 0 0 0 1 0 0\n#vertex 1 0 0 0 0 1 1 0\n"
               "#vertex 0 1 0 0 0 1 0 1\n#shape_sphere 0 0 0 0 1\n#shape_triangle 0 0 1 2\n");
    write_file("inc0.ray",
               "#material .1 .1 .1 .5 .5 .5 .2 .2 .2 0 0 0 .5 .25 1.5 -1 !m!\n"
               "#shape_box -1 0 0 0 1 1 1\n#shape_cone -1 0 0 0 1 2\n");
    write_file("inc3.ray",
               "#camera 0 0 0 0 0 0 0 0 0 0\n"
               "#material 0 0 0 .1 .1 .1 .5 .5 .5 .2 .2 .2 10 0 0 0 1 0 !m!\n"
               "#texture tex.ppm\n#vertex 0 0 0 0 0 1 0 0\n#vertex 1 0 0 0 0 1 1 0\n"
               "#vertex 0 1 0 0 0 1 0 1\n#key_file anim.key\n"
               "#shape_triangles 0 #shape_list_begin #shape_triangle 0 1 2 #shape_list_end\n"
               "#dynamic_affine arm #shape_torus 0 0 0 0 0.25 1\n");
    write_file("loop.ray", "#ray_file loop.ray\n");
    write_file("tex.ppm", "P3 2 2 255\n255 0 0  0 255 0\n0 0 255  255 255 255\n");
    write_file("anim.key", "#DOFS 1 arm #DURATION 1 #FRAMES 1\n1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
}

// A first line "#@v0", "#@v1" or "#@v3" forces that dialect (--dialect), as the programs can;
// without it the dialect is detected from the text (spec §10).
std::optional<rt::Dialect> forced_dialect(std::string* text) {
    static const std::pair<std::string_view, rt::Dialect> kForced[] = {
        {"#@v0\n", rt::Dialect::V0}, {"#@v1\n", rt::Dialect::V1}, {"#@v3\n", rt::Dialect::V3}};
    for (const auto& [prefix, dialect] : kForced)
        if (text->compare(0, prefix.size(), prefix) == 0) {
            text->erase(0, prefix.size());
            return dialect;
        }
    return std::nullopt;
}

// The tree of the centre pixel of a 4x4 image at depth 8 (at most 2^8 rays, so an input stays
// fast): its JSON must be strict, and it records no more rays than its limit.
void check_inspect(const rt::SceneDesc& desc, const rt::RenderScene& scene,
                   const rt::CompileReport& report) {
    rt::RenderSettings s;
    s.width = 4;
    s.height = 4;
    s.max_depth = 8;
    s.threads = 1;
    const rt::PixelTree tree = rt::inspect_pixel(scene, rt::make_render_plan(scene, s), s, 2, 2);
    const rt::InspectNames names{&desc, &report.prim_locs, &report.material_names};
    const std::string json = rt::inspect_json(tree, scene, names);
    rt::test::JsonValue v;
    std::string why;
    if (!rt::test::parse_strict_json(json, &v, &why)) {
        std::fprintf(stderr, "inspect_json is not strict JSON: %s\n", why.c_str());
        std::abort();
    }
    const rt::test::JsonValue& rays = v["rays"];
    if (rays.array.empty() || rays.array.size() > rt::PixelTree::kMaxRays ||
        tree.records > rt::PixelTree::kMaxRecords + scene.lights.size())
        std::abort();  // the tree's limits did not hold
    (void)rt::inspect_text(tree, scene, names);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    setup();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    setup();
    std::string text(reinterpret_cast<const char*>(data), size);
    // A '/' inside a word is never next to another '/' (a word ends where "//" starts), so
    // replacing the lone ones keeps every path inside the fixture directory.
    for (size_t i = 0; i < text.size(); ++i) {
        const bool prev = i > 0 && data[i - 1] == '/';
        const bool next = i + 1 < size && data[i + 1] == '/';
        if (text[i] == '/' && !prev && !next) text[i] = '_';
    }
    const size_t split = text.find("#@key");
    std::string key;
    if (split != std::string::npos) {
        key = text.substr(split + 5);
        text.resize(split);
    }
    write_file("fuzz.key", key);
    rt::ParseOptions options;
    options.missing_textures = rt::MissingTextures::Checker;
    options.dialect = forced_dialect(&text);
    const auto parse = [&](rt::Diagnostics& diag, const rt::ParseOptions& o) {
        return rt::parse_scene_string(text, "fuzz.ray", diag, o, rt_fuzz::work_dir());
    };
    if (rt::both_ways::outcome(parse, rt::both_ways::serial(options)) !=
        rt::both_ways::outcome(parse, rt::both_ways::in_pieces(options)))
        std::abort();  // the parse in pieces differs from the serial parse
    try {
        rt::Diagnostics diag;
        const rt::SceneDesc desc =
            rt::parse_scene_string(text, "fuzz.ray", diag, options, rt_fuzz::work_dir());
        rt::CompileReport report;
        report.record_locations = true;  // the tree names each primitive's directive
        rt::RenderScene scene = rt::compile_scene(desc, &report);
        check_inspect(desc, scene, report);
        // Every interpolation and rotation once, at times inside, before and far past the loop.
        const double times[] = {0.37, -5.1, 1e7, 2.0};
        for (int k = 0; k < 20 && !desc.tracks.empty(); ++k) {
            const rt::SceneTime t{times[k % 4], static_cast<rt::Interpolation>(k % 4),
                                  static_cast<rt::Rotation>(k % 5)};
            try {
                rt::animate(scene, desc, t, &diag);
            } catch (const rt::SceneError&) {  // a quaternion that normalizes to nothing
            }
        }
        if (!desc.tracks.empty()) (void)rt::compile_scene(rt::scene_at_time(desc, rt::SceneTime{}));
        // The viewer's in-place save of edited materials (replace_materials) on this text: each
        // of the top file's materials written back where it was read, then parsed again.
        std::vector<std::pair<rt::SourceLoc, std::string>> edits;
        for (const rt::MaterialDesc& m : desc.files[0].materials)
            edits.emplace_back(m.loc, rt::write_material(m, desc.dialect));
        if (!edits.empty()) {
            const std::string patched = rt::replace_materials(text, "fuzz.ray", std::move(edits));
            (void)rt::parse_scene_string(patched, "fuzz.ray", diag, options, rt_fuzz::work_dir());
        }
    } catch (const rt::SceneError&) {
        // The expected way for bad input to end.
    }
    return 0;
}
