// libFuzzer target: bytes -> a key file (spec §14.1), named by a fixed scene whose joints bind the
// file's first DOF names (§14.2), then compiled and animated at a few times. Any input must end in
// a SceneError or an animated scene: a crash, a sanitizer report, a hang or any other exception is
// a bug. The scene fuzzer reaches key files too (its "#@key" inputs); this target spends all its
// mutations on the key grammar. Seeds: the .key files of scenes/, the public scenes and
// tests/fuzz/corpus/key.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_util.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/scene/scene_time.h"

namespace {

// Up to four words after "#DOFS N": the names the scene's joints take, so that they bind.
std::vector<std::string> dof_names(std::string_view text) {
    std::vector<std::string> names;
    size_t at = text.find("#DOFS");
    if (at == std::string_view::npos) return names;
    at += 5;
    auto next_word = [&]() {
        while (at < text.size() &&
               std::string_view(" \t\r\n").find(text[at]) != std::string_view::npos)
            ++at;
        const size_t start = at;
        while (at < text.size() &&
               std::string_view(" \t\r\n").find(text[at]) == std::string_view::npos)
            ++at;
        return std::string(text.substr(start, at - start));
    };
    (void)next_word();  // the count
    for (int i = 0; i < 4; ++i) {
        const std::string w = next_word();
        if (w.empty() || w[0] == '#' || w.size() > 64) break;
        names.push_back(w);
    }
    return names;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)rt_fuzz::work_dir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, size_t size) {
    const std::string_view key(reinterpret_cast<const char*>(bytes), size);
    rt_fuzz::write_file("fuzz.key", key);
    std::string scene = "#key_file fuzz.key\n";
    for (const std::string& name : dof_names(key))
        scene += "#joint_begin " + name + "\n#shape_sphere -1 0 0 0 1\n#joint_end\n";
    try {
        rt::Diagnostics diag;
        const rt::SceneDesc desc =
            rt::parse_scene_string(scene, "fuzz.ray", diag, {}, rt_fuzz::work_dir());
        rt::RenderScene compiled = rt::compile_scene(desc);
        const double times[] = {0.37, -5.1, 1e7, 2.0};
        for (int k = 0; k < 8 && !desc.tracks.empty(); ++k) {
            const rt::SceneTime t{times[k % 4], static_cast<rt::Interpolation>(k % 4),
                                  static_cast<rt::Rotation>(k % 5)};
            try {
                rt::animate(compiled, desc, t, &diag);
            } catch (const rt::SceneError&) {  // a quaternion that normalizes to nothing
            }
        }
    } catch (const rt::SceneError&) {
        // The expected way for bad input to end.
    }
    return 0;
}
