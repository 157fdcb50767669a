// The meaning of the .ray directives (spec §3, §4, §10, §13, §14): what the grammar walks read,
// checked and placed into the scene description. Nothing here reads a token.
#include "format/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "format/grammar.h"
#include "rt/image/image.h"
#include "rt/util/file_io.h"
#include "rt/util/limits.h"

namespace fs = std::filesystem;

namespace rt::parser_impl {

// ---- errors and warnings ------------------------------------------------------------------------
void SceneBuilder::fail(const SourceLoc& loc, const std::string& message) const {
    std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
    throw SceneError(loc, message, std::move(chain));
}

void SceneBuilder::warn(const SourceLoc& loc, std::string kind, std::string message) const {
    std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
    warn({loc, std::move(kind), std::move(message), std::move(chain)});
}

void SceneBuilder::warn(PieceOutput::Pending&& w) const {
    if (t_piece) {
        t_piece->warnings.push_back(std::move(w));
    } else if (m_ahead) {
        Ahead::Event e;
        e.what = Ahead::Event::Warning;
        e.loc = w.loc;
        e.kind = std::move(w.kind);
        e.message = std::move(w.message);
        e.chain = std::move(w.chain);
        m_ahead->events.push_back(std::move(e));
    } else {
        m_diag.warn(w.loc, std::move(w.kind), std::move(w.message), std::move(w.chain));
    }
}

void SceneBuilder::skip_shape(const SourceLoc& loc, const char* kind) {
    if (t_piece)
        ++t_piece->skipped;
    else
        ++m_scene.skipped_shapes;
    warn(loc, std::string("skip:") + kind, std::string(kind) + " skipped");
}

std::string SceneBuilder::fmt(double v) {
    std::ostringstream ss;
    ss << v;
    return ss.str();
}

// ---- the tree -----------------------------------------------------------------------------------
void SceneBuilder::set_dialect(Dialect d, std::string v3_marker, std::string top_dir) {
    m_dialect = d;
    m_v3_marker = std::move(v3_marker);
    m_top_dir = std::move(top_dir);
}

void SceneBuilder::open_file(const std::string& canonical, const std::string& name) {
    m_open.push_back({canonical, name});
}

void SceneBuilder::check_texture_refs(const FileState& f) const {
    const int ntex = static_cast<int>(f.desc.textures.size());
    for (const FileState::TextureRef& r : f.texture_refs)
        if (r.index < -1 || r.index >= ntex)
            fail(r.loc, "texture index " + std::to_string(r.index) + " out of range [-1," +
                            std::to_string(ntex) + ")");
}

void SceneBuilder::end_of_v1_file(FileState& f, const SourceLoc& eof) {
    if (f.stack.size() > 1) {
        const GroupDesc* g = f.stack.back();
        fail(eof, std::string(f.stack_is_joint.back() ? "#joint_begin" : "#group_begin") + " at " +
                      g->loc.str() + " is never closed");
    }
    for (int k = 0; k < kCountKinds; ++k) {
        const Count& c = f.counts[static_cast<size_t>(k)];
        if (c.declared && c.found < c.declared_n)
            fail(eof, std::string(kCountDirective[static_cast<size_t>(k)]) + " at " + c.loc.str() +
                          " declares " + std::to_string(c.declared_n) + ", found " +
                          std::to_string(c.found));
    }
}

SceneDesc SceneBuilder::finish() {
    // Instancing multiplies: a file placed k times that instances another m times places it k*m
    // times. The compiler visits every placement, so their number is bounded here, where the
    // instance directives still have their locations.
    std::vector<long long> memo(m_scene.files.size(), -1);
    if (!m_scene.files.empty()) placements(0, memo);
    m_scene.dialect = m_dialect;
    if (!m_scene.camera && !m_scene.files.empty() && !m_all_zero_camera)
        warn({intern_file_name(m_scene.files[0].path), 0, 0}, "no-camera",
             "no #camera: using the default camera");
    return std::move(m_scene);
}

// The recursion follows the include tree, which is acyclic and at most kMaxIncludeDepth deep.
long long SceneBuilder::placements(size_t fi, std::vector<long long>& memo) const {
    if (memo[fi] >= 0) return memo[fi];
    const FileDesc& file = m_scene.files[fi];
    long long total = 1;  // the file itself
    std::vector<const GroupDesc*> todo = {&file.root};
    while (!todo.empty()) {
        const GroupDesc* g = todo.back();
        todo.pop_back();
        for (const InstanceDesc& in : g->instances) {
            const int sub = file.ray_files[static_cast<size_t>(in.ray_file)];
            total += placements(static_cast<size_t>(sub), memo);
            if (total > kMaxPlacements)
                fail(in.loc, "instancing places more than " + std::to_string(kMaxPlacements) +
                                 " copies of files (nested instances multiply)");
        }
        for (const GroupDesc& c : g->groups) todo.push_back(&c);
        for (const CsgDesc& c : g->csgs)
            for (const GroupDesc& o : c.operands) todo.push_back(&o);
    }
    return memo[fi] = total;
}

// ---- counts -------------------------------------------------------------------------------------
void SceneBuilder::declare_count(FileState& f, const SourceLoc& loc, CountKind k, int n,
                                 const SourceLoc& n_loc, size_t room) {
    Count& c = f.counts[k];
    if (c.declared)
        fail(loc, "second " + std::string(kCountDirective[k]) + " (first at " + c.loc.str() + ")");
    if (c.found > 0)
        fail(loc, std::string(kCountDirective[k]) + " after the first " + kItemDirective[k]);
    if (n < 0) fail(n_loc, "negative count " + std::to_string(n));
    c.declared = true;
    c.declared_n = n;
    c.loc = loc;
    // Reserve no more than the rest of the text can hold, so a huge count cannot allocate
    // before the file runs out.
    if (k == kVertices) f.desc.vertices.reserve(std::min(static_cast<size_t>(n), room));
}

void SceneBuilder::too_many(const SourceLoc& loc, CountKind k, const Count& c) const {
    fail(loc, "more " + std::string(k == kLights ? "lights" : kItemDirective[k]) +
                  " than declared by " + kCountDirective[k] + " at " + c.loc.str());
}

// ---- paths --------------------------------------------------------------------------------------
// Spec §4.2: relative to the naming file's directory, then the working directory. V3 (spec
// §13.2): the top-level file's directory first, then those two with a warning.
std::optional<std::string> SceneBuilder::try_resolve(const FileState& f, const SourceLoc& at,
                                                     const std::string& path,
                                                     std::string* tried) const {
    const fs::path p(path);
    if (p.is_absolute()) {
        if (tried) *tried = is_dir(p) ? path + " (a directory)" : "";
        return is_file(p) ? std::optional<std::string>(path) : std::nullopt;
    }
    const bool v3 = m_dialect == Dialect::V3;
    std::vector<fs::path> places;
    if (v3) places.push_back(fs::path(m_top_dir) / p);
    places.push_back(fs::path(f.dir) / p);
    places.push_back(fs::path(".") / p);
    std::vector<fs::path> unique;
    for (const fs::path& c : places)
        if (std::find_if(unique.begin(), unique.end(), [&](const fs::path& u) {
                return u.lexically_normal() == c.lexically_normal();
            }) == unique.end())
            unique.push_back(c);
    for (size_t i = 0; i < unique.size(); ++i) {
        if (!is_file(unique[i])) continue;
        const std::string found = unique[i].lexically_normal().string();
        if (v3 && i > 0)
            warn(at, "v3-path:" + path,
                 quote(path) + " found as " + found + ", not in " + m_top_dir +
                     " (V3 resolves paths against the top-level file's directory)");
        return found;
    }
    if (tried) {
        // A directory of that name is found but not taken: said so, not left to look missing.
        tried->clear();
        for (const fs::path& c : unique)
            *tried +=
                (tried->empty() ? "" : ", ") + c.string() + (is_dir(c) ? " (a directory)" : "");
    }
    return std::nullopt;
}

std::string SceneBuilder::resolve(const FileState& f, const SourceLoc& at, const std::string& path,
                                  const std::string& what) const {
    std::string tried;
    if (auto found = try_resolve(f, at, path, &tried)) return *found;
    if (tried.empty()) fail(at, "cannot open " + what + " " + quote(path));
    fail(at, "cannot open " + what + " " + quote(path) + " (tried " + tried + ")");
}

// ---- camera, lights, the global settings --------------------------------------------------------
bool SceneBuilder::dummy_camera(const CameraDesc& c) {
    if (c.position != Vec3(0.0) || c.direction != Vec3(0.0) || c.up != Vec3(0.0) ||
        c.half_height_angle_rad != 0.0)
        return false;
    warn(c.loc, "camera-zero", "all-zero #camera (a sub-file's dummy): using the default camera");
    m_all_zero_camera = true;
    return true;
}

void SceneBuilder::check_camera(const CameraDesc& c) const {
    if (glm::length(c.direction) == 0.0) fail(c.loc, "camera view direction is zero");
    if (glm::length(c.up) == 0.0) fail(c.loc, "camera up vector is zero");
    if (glm::length(glm::cross(glm::normalize(c.direction), glm::normalize(c.up))) < 1e-6)
        fail(c.loc, "camera up vector is parallel to the view direction");
    if (!(c.half_height_angle_rad > 0.0 && c.half_height_angle_rad < kPi / 2))
        fail(c.loc, "camera half-height angle " + fmt(c.half_height_angle_rad) +
                        " is outside (0, pi/2) radians");
}

void SceneBuilder::camera(const FileState& f, const CameraDesc& c) {
    // Included files: syntax only, so the dummy all-zero cameras of sub-files pass (§3.1, §12).
    if (!f.top) return;
    if (m_dialect == Dialect::V3) {
        // Spec §13.3: the last #camera wins; an all-zero one is the default camera.
        if (m_camera_loc.file)
            warn(c.loc, "camera-repeat",
                 "second #camera: the last one wins (the earlier one is at " + m_camera_loc.str() +
                     ")");
        m_camera_loc = c.loc;
        if (dummy_camera(c)) {
            m_scene.camera.reset();
            return;
        }
        check_camera(c);
        m_scene.camera = c;
        return;
    }
    // The course's V3 sub-files without a V3 marker read as V1 (§10 step 4), and opened on their
    // own they should render as V3 ones do (§13.3): the dummy camera (never a valid camera) is
    // the default camera with a warning in every dialect. Otherwise the first one wins.
    if (!m_scene.camera && dummy_camera(c)) return;
    check_camera(c);
    if (m_scene.camera) {
        warn(c.loc, "camera-repeat",
             "second #camera ignored; the first one (" + m_scene.camera->loc.str() + ") wins");
        return;
    }
    m_scene.camera = c;
}

void SceneBuilder::global_colour(const FileState& f, bool background, const SourceLoc& loc,
                                 const Vec3& c) {
    if (!f.top) return;  // included files: syntax only
    bool& seen = background ? m_seen_background : m_seen_ambient;
    const std::string name = background ? "#background" : "#ambient";
    if (seen) {
        warn(loc, name + "-repeat", "repeated " + name + " ignored; the first one wins");
        return;
    }
    seen = true;
    (background ? m_scene.background : m_scene.ambient) = c;
}

void SceneBuilder::attenuation(const LightDesc& l) const {
    if (l.kind != LightKind::Directional && l.constant_atten == 0.0 && l.linear_atten == 0.0 &&
        l.quadratic_atten == 0.0)
        warn(l.loc, "light-zero-atten",
             "attenuation coefficients are all zero: the light never contributes");
}

void SceneBuilder::spot_cutoff(const LightDesc& l) const {
    if (l.kind == LightKind::Spot && l.cutoff_rad > kPi / 2)
        warn(l.loc, "spot-cutoff",
             "spot cutoff " + fmt(l.cutoff_rad) +
                 " rad is more than pi/2: the light never cuts off");
}

void SceneBuilder::light(FileState& f, const LightDesc& l) {
    if (m_dialect != Dialect::V3) count_item(f, l.loc, kLights);
    if (!f.top) {
        // V3 warns once per file.
        if (m_dialect != Dialect::V3 || !f.warned_included_light)
            warn(l.loc, "included-light", "lights in included files are ignored");
        f.warned_included_light = true;
        return;
    }
    m_scene.lights.push_back(l);
}

void SceneBuilder::shader(const FileState& f, std::string vertex, std::string fragment) {
    if (!f.top) return;  // spec §13.3: recorded (the last one wins), never opened
    m_scene.shader_vertex = std::move(vertex);
    m_scene.shader_fragment = std::move(fragment);
}

// ---- definitions --------------------------------------------------------------------------------
TextureCache::Decoded SceneBuilder::decode_once(const std::string& path) {
    const std::lock_guard<std::mutex> lock(m_textures->mutex);
    const auto [it, added] = m_textures->decoded.try_emplace(canonical_path(path));
    if (added) {
        // Each texture decodes within what the scene's texel budget has left, so the #texture
        // that would pass it is refused before its pixels are allocated. (Files parsed ahead
        // decode their textures as their threads reach them: in a tree over the budget, the
        // #texture refused may be another than the serial parse's; the total holds either way.)
        const uint64_t budget = max_scene_texels();
        const uint64_t left = budget - std::min(budget, m_textures->texels);
        const DecodeBudget scope(left, "what is left of the scene's texture budget (" +
                                           std::to_string(left) + " of " + std::to_string(budget) +
                                           " texels, 4 x --max-pixels)");
        auto image = std::make_shared<TextureImage>();
        if (load_texture_image(path, image.get(), &it->second.error)) {
            m_textures->texels += static_cast<uint64_t>(image->width) * image->height;
            it->second.image = std::move(image);
        }
    }
    return it->second;
}

void SceneBuilder::texture(FileState& f, const SourceLoc& loc, const SourceLoc& path_loc,
                           const std::string& path) {
    TextureDesc t;
    t.loc = loc;
    std::string tried, problem;
    const std::optional<std::string> found = try_resolve(f, path_loc, path, &tried);
    if (found) {
        t.path = *found;
        const TextureCache::Decoded decoded = decode_once(t.path);
        t.image = decoded.image;
        if (!t.image) problem = "cannot decode texture " + quote(t.path) + ": " + decoded.error;
    } else {
        t.path = path;
        problem = "cannot open texture " + quote(path) +
                  (tried.empty() ? std::string() : " (tried " + tried + ")");
    }
    if (!problem.empty()) {
        if (m_options.missing_textures != MissingTextures::Checker) fail(path_loc, problem);
        t.image = std::make_shared<const TextureImage>(checker_texture());
        missing_texture(path_loc, path, problem + "; a checker stands in");
    }
    f.desc.textures.push_back(std::move(t));
}

// --missing-textures checker: a loud stand-in, one warning per missing file (in the tree's
// order: a file parsed ahead leaves it to its replay).
void SceneBuilder::missing_texture(const SourceLoc& loc, const std::string& path,
                                   std::string message) {
    if (m_ahead) {
        Ahead::Event e;
        e.what = Ahead::Event::MissingTexture;
        e.loc = loc;
        e.path = path;
        e.message = std::move(message);
        m_ahead->events.push_back(std::move(e));
        return;
    }
    const auto& missing = m_scene.missing_textures;
    if (std::find(missing.begin(), missing.end(), path) != missing.end()) return;
    m_scene.missing_textures.push_back(path);
    warn(loc, "missing-texture:" + path, std::move(message));
}

// The colours and terms by position in the tree's dialect.
MaterialDesc SceneBuilder::material(const MaterialNumbers& w) const {
    const Dialect dialect = w.n == 16 ? Dialect::V0 : Dialect::V1;
    if (dialect != (m_dialect == Dialect::V3 ? Dialect::V1 : m_dialect))  // pre-scan first
        fail(w.loc, "#material has " + std::to_string(w.n) + " numbers in a " +
                        dialect_name(m_dialect) + " scene");
    MaterialDesc m;
    m.loc = w.loc;
    m.name = w.name;
    const auto& v = w.v;
    auto rgb = [&](int i, const char* what) {
        const Vec3 c(v[static_cast<size_t>(i)], v[static_cast<size_t>(i) + 1],
                     v[static_cast<size_t>(i) + 2]);
        for (int k = 0; k < 3; ++k)
            if (c[k] < 0)
                fail(w.at[static_cast<size_t>(i + k)],
                     std::string("negative ") + what + " " + fmt(c[k]));
        return c;
    };
    auto nonneg = [&](int i, const char* what) {
        const double x = v[static_cast<size_t>(i)];
        if (x < 0)
            fail(w.at[static_cast<size_t>(i)], std::string("negative ") + what + " " + fmt(x));
        return x;
    };
    int ior_i = 0;
    if (dialect == Dialect::V0) {
        // ambient, diffuse, specular, emissive, kspec, ktran, refind, tex
        m.ambient = rgb(0, "ambient");
        m.diffuse = rgb(3, "diffuse");
        m.specular = rgb(6, "specular");
        m.emissive = rgb(9, "emissive");
        m.specular_exponent = kV0ExponentScale * nonneg(12, "kspec");
        m.transparent = Vec3(nonneg(13, "ktran"));
        ior_i = 14;
    } else {
        // emissive, ambient, diffuse, specular, n, transparent, refind, tex
        m.emissive = rgb(0, "emissive");
        m.ambient = rgb(3, "ambient");
        m.diffuse = rgb(6, "diffuse");
        m.specular = rgb(9, "specular");
        m.specular_exponent = nonneg(12, "specular exponent");
        m.transparent = rgb(13, "transparency");
        ior_i = 16;
    }
    m.refractive_index = v[static_cast<size_t>(ior_i)];
    if (m.refractive_index <= 0) {
        warn(w.at[static_cast<size_t>(ior_i)], "refind",
             "refractive index " + fmt(m.refractive_index) + " <= 0; 1 is used");
        m.refractive_index = 1.0;
    }
    return m;
}

void SceneBuilder::add_material(FileState& f, MaterialDesc m, const SourceLoc& texture_loc) const {
    // Definitions may come in any order: the range is checked at the end of the file.
    f.texture_refs.push_back({texture_loc, m.texture});
    f.desc.materials.push_back(std::move(m));
}

void SceneBuilder::vertex(FileState& f, const SourceLoc& loc, VertexDesc v) const {
    const double len = glm::length(v.normal);
    if (len > 0) v.normal /= len;
    add_vertex(f, loc, v);
}

void SceneBuilder::ray_file(FileState& f, const SourceLoc& loc, const SourceLoc& path_loc,
                            const std::string& path) {
    const std::string resolved = resolve(f, path_loc, path, "ray file");
    if (m_ahead) {  // numbered and parsed when the replay reaches it
        Ahead::Event e;
        e.what = Ahead::Event::Include;
        e.loc = loc;
        e.path_loc = path_loc;
        e.path = path;
        e.resolved = resolved;
        e.index = f.desc.ray_files.size();
        m_ahead->events.push_back(std::move(e));
        f.desc.ray_files.push_back(-1);
        return;
    }
    f.desc.ray_files.push_back(include(loc, path_loc, resolved));
}

int SceneBuilder::include(const SourceLoc& loc, const SourceLoc& path_loc,
                          const std::string& resolved) {
    const std::string canonical = canonical_path(resolved);
    // A file that (transitively) includes itself is an error naming the chain.
    for (size_t i = 0; i < m_open.size(); ++i) {
        if (m_open[i].canonical == canonical) {
            std::string chain;
            for (size_t k = i; k < m_open.size(); ++k)
                chain += fs::path(m_open[k].name).filename().string() + " -> ";
            chain += fs::path(resolved).filename().string();
            fail(path_loc, "include cycle: " + chain);
        }
    }
    if (m_open.size() >= static_cast<size_t>(kMaxIncludeDepth))
        fail(loc, "#ray_file includes nested deeper than " + std::to_string(kMaxIncludeDepth) +
                      " files");
    for (size_t i = 0; i < m_scene.files.size(); ++i)
        if (m_scene.files[i].canonical_path == canonical) return static_cast<int>(i);
    std::string why;
    if (!m_files->readable(resolved, canonical, &why))
        fail(path_loc, read_failure("cannot read ray file", resolved, why));
    const int index = static_cast<int>(m_scene.files.size());
    m_scene.files.emplace_back();
    m_scene.files.back().canonical_path = canonical;  // reserve the identity
    m_include_locs.push_back(loc);
    m_files->parse(resolved, canonical, index);
    m_include_locs.pop_back();
    return index;
}

void SceneBuilder::replay(Ahead& a, int index) {
    open_file(a.canonical, a.name);
    std::vector<SourceLoc> outer(m_include_locs.rbegin(), m_include_locs.rend());
    const auto chained = [&](std::vector<SourceLoc> chain) {
        chain.insert(chain.end(), outer.begin(), outer.end());
        return chain;
    };
    std::vector<int> track_of(a.tracks.size(), -1);
    for (Ahead::Event& e : a.events) {
        switch (e.what) {
            case Ahead::Event::Warning:
                m_diag.warn(e.loc, std::move(e.kind), std::move(e.message), chained(e.chain));
                break;
            case Ahead::Event::Include: {
                const int sub = include(e.loc, e.path_loc, e.resolved);
                if (e.index < a.desc.ray_files.size()) a.desc.ray_files[e.index] = sub;
                break;
            }
            case Ahead::Event::Track:
                track_of[e.index] = static_cast<int>(m_scene.tracks.size());
                m_scene.tracks.push_back(a.tracks[e.index]);
                break;
            case Ahead::Event::MissingTexture:
                missing_texture(e.loc, e.path, std::move(e.message));
                break;
        }
    }
    if (a.error) {
        try {
            std::rethrow_exception(a.error);
        } catch (const SceneError& e) {
            throw SceneError(e.loc(), e.message(), chained(e.included_from()));
        }
    }
    m_scene.skipped_shapes += a.skipped;
    // The joints' tracks, numbered in the tree's order.
    std::vector<GroupDesc*> todo = {&a.desc.root};
    while (!todo.empty()) {
        GroupDesc* g = todo.back();
        todo.pop_back();
        if (g->track >= 0) g->track = track_of[static_cast<size_t>(g->track)];
        for (GroupDesc& c : g->groups) todo.push_back(&c);
        for (CsgDesc& c : g->csgs)
            for (GroupDesc& o : c.operands) todo.push_back(&o);
    }
    close_file();
    m_scene.files[static_cast<size_t>(index)] = std::move(a.desc);
}

void SceneBuilder::key_file(FileState& f, const SourceLoc& loc, const SourceLoc& path_loc,
                            const std::string& path) {
    const std::string resolved = resolve(f, path_loc, path, "key file");
    std::string text, why;
    if (!read_file(resolved, &text, &why))
        fail(path_loc, read_failure("cannot read key file", resolved, why));
    m_include_locs.push_back(loc);
    f.key_files.push_back(parse_key_file(*this, text, resolved));
    f.key_files.back().named = path;
    f.desc.key_files.push_back(resolved);
    m_include_locs.pop_back();
}

// Spec §14.2: the DOF `name` among the file's key files (the first that has it wins; an exact
// match first, else one ignoring ASCII case, with a warning); its track in the scene.
int SceneBuilder::bind_dof(FileState& f, const SourceLoc& name_loc, const std::string& name) {
    KeyFile* hit = nullptr;
    size_t dof = 0;
    const std::string key = lower(name);
    for (KeyFile& k : f.key_files) {
        // The exact match, else every DOF that matches ignoring case (`here` the last of them).
        std::vector<size_t> similar;
        size_t here = 0;
        if (const auto exact = k.by_name.find(name); exact != k.by_name.end()) {
            here = exact->second;
        } else if (const auto folded = k.by_lower_name.find(key); folded != k.by_lower_name.end()) {
            similar = folded->second;
            here = similar.back();
        } else {
            continue;
        }
        if (hit) {
            warn(name_loc, "dof-repeat",
                 "DOF " + quote(k.names[here]) + " is also in " + quote(k.named) +
                     "; the first key file (" + quote(hit->named) + ") wins");
            continue;
        }
        if (similar.size() > 1) {
            std::string list;
            for (size_t s : similar) list += (list.empty() ? "" : ", ") + quote(k.names[s]);
            fail(name_loc, "joint " + quote(name) + " matches several DOFs of " + quote(k.named) +
                               " when case is ignored: " + list);
        }
        hit = &k, dof = similar.empty() ? here : similar.front();
    }
    if (!hit) {
        std::string names;
        for (const KeyFile& k : f.key_files) names += (names.empty() ? "" : ", ") + k.named;
        fail(name_loc, "no DOF " + quote(name) + " in key files " + names);
    }
    if (hit->names[dof] != name)
        warn(name_loc, "joint-case",
             "joint " + quote(name) + " matches DOF " + quote(hit->names[dof]) +
                 " only when case is ignored");
    int& track = hit->track[dof];
    if (track < 0) {
        track = static_cast<int>(m_scene.tracks.size());
        KeyTrack t;
        t.name = hit->names[dof];
        t.duration = hit->duration;
        t.keys = hit->keys[dof];
        t.loc = name_loc;
        m_scene.tracks.push_back(std::move(t));
        if (m_ahead) {
            Ahead::Event e;
            e.what = Ahead::Event::Track;
            e.index = static_cast<size_t>(track);
            m_ahead->events.push_back(std::move(e));
        }
    }
    return track;
}

// ---- the scene graph ----------------------------------------------------------------------------
int SceneBuilder::material_index(const FileState& f, const SourceLoc& loc, int m) const {
    const int n = static_cast<int>(f.defs().materials.size());
    const bool v0_default = (m == -1 && m_dialect == Dialect::V0);
    if (!v0_default && (m < 0 || m >= n)) {
        std::string msg = "material index " + std::to_string(m) + " out of range [" +
                          (m_dialect == Dialect::V0 ? "-1," : "0,") + std::to_string(n) + ")";
        if (m == -1) msg += " (-1 is V0 only; try --dialect v0)";
        fail(loc, msg);
    }
    return m;
}

void SceneBuilder::instance_index(const FileState& f, const SourceLoc& loc, int i) const {
    const int n = static_cast<int>(f.desc.ray_files.size());
    if (i < 0 || i >= n)
        fail(loc,
             "ray file index " + std::to_string(i) + " out of range [0," + std::to_string(n) + ")");
}

void SceneBuilder::vertex_out_of_range(const FileState& f, const SourceLoc& loc, int v) const {
    const int nv = static_cast<int>(f.defs().vertices.size());
    fail(loc, "vertex index " + std::to_string(v) + " out of range [0," + std::to_string(nv) + ")");
}

bool SceneBuilder::degenerate_triangle(const FileDesc& file, const TriangleDesc& t) {
    // Spec §3.3: a repeated index, or |e1 x e2| <= 1e-12 |e1| |e2|.
    if (t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[0] == t.v[2]) return true;
    const Vec3& p0 = file.vertices[static_cast<size_t>(t.v[0])].position;
    const Vec3 e1 = file.vertices[static_cast<size_t>(t.v[1])].position - p0;
    const Vec3 e2 = file.vertices[static_cast<size_t>(t.v[2])].position - p0;
    return glm::length(glm::cross(e1, e2)) <= 1e-12 * glm::length(e1) * glm::length(e2);
}

bool SceneBuilder::keep_shape(const FileState& f, const ShapeDesc& s, const char* empty) {
    if (const auto* t = std::get_if<TriangleDesc>(&s.geometry);
        t && degenerate_triangle(f.defs(), *t)) {
        skip_shape(s.loc, "degenerate triangle");
        return false;
    }
    if (!empty) return true;
    skip_shape(s.loc, empty);
    return false;
}

void SceneBuilder::check_matrix(const Mat4& m, const SourceLoc& loc,
                                const std::string& what) const {
    // Spec §3.3 / §4.1: affine (bottom row 0 0 0 1) and non-singular.
    if (std::abs(m[0][3]) > 1e-9 || std::abs(m[1][3]) > 1e-9 || std::abs(m[2][3]) > 1e-9 ||
        std::abs(m[3][3] - 1.0) > 1e-9)
        fail(loc, "projective " + what + ": the bottom row must be 0 0 0 1");
    const Mat3 a(m);
    if (!std::isfinite(glm::determinant(a)) ||
        !std::isfinite(std::hypot(a[0].x, a[0].y, a[0].z) * std::hypot(a[1].x, a[1].y, a[1].z) *
                       std::hypot(a[2].x, a[2].y, a[2].z)))
        fail(loc, what + " too large: its determinant overflows");
    if (singular_3x3(a)) fail(loc, "singular " + what);
}

void SceneBuilder::group_begin(FileState& f, const SourceLoc& loc, const std::string& directive,
                               const Mat4& m) {
    graph(f);
    if (f.stack.size() > static_cast<size_t>(kMaxGroupDepth))
        fail(loc,
             directive + " nests groups deeper than " + std::to_string(kMaxGroupDepth) + " levels");
    check_matrix(m, loc, "group matrix");
    GroupDesc g;
    g.loc = loc;
    g.matrix = m;
    GroupDesc* parent = f.stack.back();
    parent->groups.push_back(std::move(g));
    f.stack.push_back(&parent->groups.back());
    f.stack_is_joint.push_back(0);
}

void SceneBuilder::joint_begin(FileState& f, const SourceLoc& loc, const std::string& directive,
                               const SourceLoc& name_loc, const std::string& name) {
    graph(f);
    if (f.stack.size() > static_cast<size_t>(kMaxGroupDepth))
        fail(loc,
             directive + " nests groups deeper than " + std::to_string(kMaxGroupDepth) + " levels");
    GroupDesc g;
    g.loc = loc;
    g.joint = name;
    // Spec §4.4, §14.2: the DOF of that name in the file's key files, key 0 as read.
    if (f.key_files.empty()) {
        if (!f.warned_joint_identity)
            warn(g.loc, "joint-no-key", "no #key_file: joints use the identity");
        f.warned_joint_identity = true;
    } else {
        g.track = bind_dof(f, name_loc, g.joint);
        g.matrix = m_scene.tracks[static_cast<size_t>(g.track)].keys[0];
    }
    GroupDesc* parent = f.stack.back();
    parent->groups.push_back(std::move(g));
    f.stack.push_back(&parent->groups.back());
    f.stack_is_joint.push_back(1);
}

void SceneBuilder::group_end(FileState& f, const SourceLoc& loc, const std::string& directive,
                             bool joint) {
    graph(f);
    if (f.stack.size() <= 1 || (f.stack_is_joint.back() != 0) != joint) {
        if (f.stack.size() > 1)
            fail(loc, directive + " does not match " +
                          (f.stack_is_joint.back() ? "#joint_begin" : "#group_begin") + " at " +
                          f.stack.back()->loc.str());
        fail(loc, directive + " without " + (joint ? "#joint_begin" : "#group_begin"));
    }
    f.stack.pop_back();
    f.stack_is_joint.pop_back();
}

void SceneBuilder::instance(FileState& f, const SourceLoc& loc, const SourceLoc& index_loc, int i) {
    graph(f);
    instance_index(f, index_loc, i);
    f.stack.back()->instances.push_back({loc, i});
}

int SceneBuilder::dynamic_dof(FileState& f, const SourceLoc& loc, const SourceLoc& name_loc,
                              const std::string& name) {
    if (!f.key_files.empty()) return bind_dof(f, name_loc, name);
    if (!f.warned_dynamic_identity)
        warn(loc, "joint-no-key", "no #key_file: #dynamic_affine uses the identity");
    f.warned_dynamic_identity = true;
    return -1;
}

// ---- the constructs of a V3 shapes part ---------------------------------------------------------
std::string SceneBuilder::v3_open_message(const V3Frame& fr, const std::string& what) {
    const std::string at = fr.name + " at " + fr.loc.str();
    switch (fr.kind) {
        case V3Frame::Affine:
            return at + " has no shape before " + what;
        case V3Frame::Difference:
            return at + " needs two shapes, got " + std::to_string(fr.csg.operands.size()) +
                   " before " + what;
        case V3Frame::CsgHead:
        case V3Frame::TrianglesHead:
            return at + " expects #shape_list_begin, got " + what;
        case V3Frame::List:
            return at + " is never closed";
        default:
            break;
    }
    return "the #shape_list_begin of " + at + " is never closed";
}

namespace v3_constructs {
namespace {

// Adds a finished shape to a list.
void add(GroupDesc& g, V3Node& node) {
    switch (node.kind) {
        case V3Node::Shape:
            g.shapes.push_back(std::move(node.shape));
            break;
        case V3Node::Instance:
            g.instances.push_back(node.instance);
            break;
        case V3Node::Group:
        case V3Node::List:
            g.groups.push_back(std::move(node.group));
            break;
        case V3Node::Csg:
            g.csgs.push_back(std::move(node.csg));
            break;
        case V3Node::Empty:
            break;
    }
}

// The folding of scene_desc.h: a transform or CSG operand whose child is a #shape_list_begin
// list is that list.
void receive(V3Frame& to, V3Node& node) {
    if (to.kind == V3Frame::Affine) {
        to.has_child = true;
        if (node.kind != V3Node::List) return add(to.group, node);
        const Mat4 m = to.group.matrix;
        std::string joint = std::move(to.group.joint);
        const int track = to.group.track;
        const SourceLoc loc = to.group.loc;
        to.group = std::move(node.group);
        to.group.matrix = m;
        to.group.joint = std::move(joint);
        to.group.track = track;
        to.group.loc = loc;
        return;
    }
    if (to.kind == V3Frame::CsgList || to.kind == V3Frame::Difference) {
        GroupDesc operand;
        operand.loc = node.loc;
        if (node.kind == V3Node::List)
            operand = std::move(node.group);
        else
            add(operand, node);
        to.csg.operands.push_back(std::move(operand));
        return;
    }
    add(to.group, node);  // Root, List
}

V3Node finished(const SceneBuilder& b, FileState& f, V3Frame& fr) {
    V3Node node;
    node.loc = fr.loc;
    switch (fr.kind) {
        case V3Frame::List:
            node.kind = V3Node::List;
            node.group = std::move(fr.group);
            break;
        case V3Frame::CsgList:
        case V3Frame::Difference:
            if (fr.csg.operands.empty())
                b.warn(fr.loc, "csg-empty", fr.name + " with an empty list: the node is empty");
            --f.v3_csg_depth;
            node.kind = V3Node::Csg;
            node.csg = std::move(fr.csg);
            break;
        default:  // Affine, Triangles
            node.kind = V3Node::Group;
            node.group = std::move(fr.group);
            break;
    }
    return node;
}

// Hands a finished shape to the innermost open construct, closing every construct it completes
// (a transform after its one shape, a difference after its second).

}  // namespace
}  // namespace v3_constructs

void SceneBuilder::v3_deliver(FileState& f, V3Node node) const {
    for (;;) {
        V3Frame& to = f.v3.back();
        v3_constructs::receive(to, node);
        const bool done = (to.kind == V3Frame::Affine && to.has_child) ||
                          (to.kind == V3Frame::Difference && to.csg.operands.size() == 2);
        if (!done) return;
        V3Frame fr = std::move(f.v3.back());
        f.v3.pop_back();
        node = v3_constructs::finished(*this, f, fr);
    }
}

// Opens a construct, within the nesting limits (no consumer recurses deeper than them).
V3Frame& SceneBuilder::v3_open(FileState& f, const SourceLoc& loc, std::string_view directive,
                               V3Frame::Kind kind) const {
    if (f.v3.size() > static_cast<size_t>(kMaxV3Depth))
        fail(loc, quote(directive) + " nests V3 shapes deeper than " + std::to_string(kMaxV3Depth) +
                      " levels");
    const bool csg = kind == V3Frame::CsgHead || kind == V3Frame::Difference;
    if (csg && f.v3_csg_depth >= kMaxCsgDepth)
        fail(loc, quote(directive) + " nests CSG nodes deeper than " +
                      std::to_string(kMaxCsgDepth) + " levels");
    if (csg) ++f.v3_csg_depth;
    V3Frame fr;
    fr.kind = kind;
    fr.loc = loc;
    fr.name = std::string(directive);
    fr.group.loc = fr.loc;
    fr.csg.loc = fr.loc;
    f.v3.push_back(std::move(fr));
    return f.v3.back();
}

void SceneBuilder::v3_close(FileState& f) const {
    V3Frame fr = std::move(f.v3.back());
    f.v3.pop_back();
    v3_deliver(f, v3_constructs::finished(*this, f, fr));
}

void SceneBuilder::v3_end_of_file(FileState& f, const SourceLoc& eof) const {
    if (f.v3.size() > 1) fail(eof, v3_open_message(f.v3.back(), "end of file"));
    f.desc.root = std::move(f.v3.back().group);
    f.desc.root.loc = {};
    f.v3.clear();
}

}  // namespace rt::parser_impl
