#include "state/viewer_output.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "frames.h"
#include "rt/compile/compile.h"
#include "rt/format/writer.h"
#include "rt/util/file_io.h"
#include "rt/util/limits.h"

namespace rt::view {

namespace {

// The background job on a copy of the scene with the latest edits, at the display's settings; an
// image over --max-pixels is refused here, as raytrace refuses it, before anything is allocated.
bool start_render(ViewerState& v, const std::string& path, int width, int height, int spp,
                  const SequenceSpec& sequence) {
    if (const std::string e =
            image_size_error(static_cast<uint64_t>(std::max(width, 0)),
                             static_cast<uint64_t>(std::max(height, 0)), "an image");
        !e.empty()) {
        v.messages.fail("cannot render " + path + ": " + e);
        return false;
    }
    ImageJobSpec spec;
    spec.path = path;
    spec.width = width;
    spec.height = height;
    spec.spp = spp;
    spec.settings = v.settings.render;
    spec.exposure = v.settings.exposure;
    spec.tonemap = v.settings.tonemap;
    spec.sequence = sequence;
    RenderScene scene = v.session.loaded->scene;  // shares its sets: the copy costs the instances
    apply_edits(v.edits, v.session.loaded->material_origins, v.headlight_on(), width, height,
                &scene, &spec.settings);
    v.jobs.image.start(std::move(scene), spec);
    return true;
}

}  // namespace

std::vector<std::string> edited_included_files(const ViewerState& v) {
    std::vector<std::string> files;
    if (!v.session.loaded) return files;
    const LoadedScene& s = *v.session.loaded;
    for (size_t k = 0; k < v.edits.materials.size(); ++k) {
        const MaterialOrigin o = s.origin(k);
        if (o.file <= 0 ||
            static_cast<const Material&>(v.edits.materials[k]) == s.file_materials.at(k))
            continue;
        const std::string& path = s.desc.files[static_cast<size_t>(o.file)].path;
        if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
    }
    return files;
}

void save_scene(const ViewerState& v, const std::string& path, bool included_too) {
    const LoadedScene& s = *v.session.loaded;
    SceneDesc desc = s.desc;
    desc.camera = v.edits.camera.desc();
    desc.lights.clear();
    for (size_t i = 0; i < v.edits.lights.size(); ++i)
        if (v.edits.light_on[i]) desc.lights.push_back(v.edits.lights[i]);
    // The edited materials into their files' descriptions, where the file has them now (a
    // reload may have moved their lines); an included file's edited directives, as text, to
    // replace in that file.
    std::map<size_t, std::vector<std::pair<SourceLoc, std::string>>> included;
    for (size_t k = 0; k < v.edits.materials.size(); ++k) {
        const MaterialOrigin o = s.origin(k);
        if (o.file < 0) continue;  // the built-in default
        const MaterialDesc& m = v.edits.materials[k];
        MaterialDesc& md =
            desc.files[static_cast<size_t>(o.file)].materials[static_cast<size_t>(o.index)];
        const SourceLoc loc = md.loc;
        std::string name = md.name;
        md = m;
        md.loc = loc;
        md.name = std::move(name);
        if (included_too && o.file > 0 &&
            !(static_cast<const Material&>(m) == s.file_materials.at(k)))
            included[static_cast<size_t>(o.file)].emplace_back(md.loc,
                                                               write_material(md, desc.dialect));
    }
    std::vector<std::pair<std::string, std::string>> writes{{path, write_scene_for(desc, path)}};
    for (auto& [f, changes] : included) {
        const std::string& file = desc.files[f].path;
        std::string text, why;
        if (!read_file(file, &text, &why)) throw std::runtime_error(file + ": " + why);
        writes.emplace_back(file, replace_materials(text, file, std::move(changes)));
    }
    for (const auto& [file, text] : writes)
        write_file_atomic(file, text);  // a temporary name, then renamed
    if (v.hooks.on_saved) v.hooks.on_saved(path);
}

void save_trace(const ViewerState& v, const std::string& path) {
    if (v.trace.last_trace.width == 0) throw std::runtime_error("nothing traced yet");
    save_image(holds_linear(image_format_from_path(path)) ? v.trace.last_trace : displayed_trace(v),
               path);
    if (v.hooks.on_saved) v.hooks.on_saved(path);
}

Image displayed_trace(const ViewerState& v) {
    return display_transform(v.trace.last_trace, v.settings.exposure, v.settings.tonemap);
}

void render_animation(ViewerState& v, const std::string& pattern, int frames, int width, int height,
                      int spp, const std::string& video) {
    if (!v.session.loaded) return;
    try {
        rtapp::frame_path(pattern, 0);
    } catch (const std::invalid_argument& e) {
        v.messages.fail(std::string("render animation: ") + e.what());
        return;
    }
    SequenceSpec q;
    q.desc = std::make_shared<const SceneDesc>(v.session.loaded->desc);
    q.frames = frames;
    q.fps = v.timeline.fps;
    q.interpolation = v.timeline.interpolation;
    q.rotation = v.timeline.rotation;
    q.video = video;
    if (!start_render(v, pattern, width, height, spp, q)) return;
    v.jobs.image_path.clear();
    v.messages.note("rendering " + std::to_string(frames) + " frames to " + pattern + " ...");
}

void render_image(ViewerState& v, const std::string& path, int width, int height, int spp) {
    if (!v.session.loaded || !start_render(v, path, width, height, spp, {})) return;
    v.jobs.image_path = path;  // one file (an animation's frames are not handed to on_saved)
    v.messages.note("rendering " + path + " ...");
}

}  // namespace rt::view
