// The meaning of the .ray directives (spec §3, §4, §10, §13, §14): what the grammar walks read,
// checked and placed into the scene description, file by open file; and the merge of a copy's
// result in the tree's order. Nothing here reads a token.
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

std::string fmt(double v) {
    std::ostringstream ss;
    ss << v;
    return ss.str();
}

std::string too_many_message(CountKind k, const Count& c) {
    return "more " + std::string(k == kLights ? "lights" : kItemDirective[k]) +
           " than declared by " + kCountDirective[k] + " at " + c.loc.str();
}

namespace {

std::string v3_open_message(const V3Frame& fr, const std::string& what);
bool degenerate_triangle(const FileDesc& file, const TriangleDesc& t);
void check_matrix(const SceneBuilder& b, const Mat4& m, const SourceLoc& loc,
                  const std::string& what);
long long placements(const SceneBuilder& b, const SceneDesc& scene, size_t fi,
                     std::vector<long long>& memo);

}  // namespace

SceneBuilder::SceneBuilder(Diagnostics& diag, const ParseOptions& options)
    : m_diag(diag), m_options(options), m_textures(std::make_shared<TextureCache>()) {}

SceneBuilder::SceneBuilder(const SceneBuilder& from, Diagnostics& own, std::optional<Piece> piece)
    : m_diag(own),
      m_options(from.m_options),
      m_dialect(from.m_dialect),
      m_top_dir(from.m_top_dir),
      m_textures(from.m_textures),
      m_copy(Copy{}) {
    if (!piece) return;
    // A piece starts from its file's state as the run's first directive left it.
    m_copy->piece = true;
    m_include_locs = from.m_include_locs;
    const OpenFile& f = *from.m_file;
    auto& s = *m_open.emplace_back(std::make_unique<OpenFile>());
    m_file = &s;
    s.defs = f.defs;
    s.top = f.top;
    s.dir = f.dir;
    s.graph_started = f.graph_started;
    s.counts = f.counts;
    if (piece->vertices) s.counts[kVertices].found += static_cast<int>(piece->index) - 1;
    s.v3_part = f.v3_part;
    s.stack.push_back(&s.desc.root);
    s.stack_is_joint.push_back(0);
    if (!f.v3.empty()) {
        s.v3.emplace_back();
        s.v3.back().kind = f.v3.back().kind;
        s.v3.back().material = f.v3.back().material;
    }
    // Its range of the run's room: directive i of the run writes place i - 1.
    const size_t at = piece->index - 1;
    if (piece->vertices) {
        VertexDesc* first = f.run.vertex_room + at;
        s.lent_vertices = {first, first, first + piece->count};
    } else {
        ShapeDesc* first = f.run.shape_room + at;
        s.lent_shapes = {first, first, first + piece->count};
    }
}

// ---- errors and warnings ------------------------------------------------------------------------
void SceneBuilder::fail(const SourceLoc& loc, const std::string& message) const {
    std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
    throw SceneError(loc, message, std::move(chain));
}

void SceneBuilder::warn(const SourceLoc& loc, std::string kind, std::string message) const {
    std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
    m_diag.warn(loc, std::move(kind), std::move(message), std::move(chain));
}

namespace {

// A degenerate or empty shape left out, with its warning ("degenerate triangle skipped").
void skip_shape(const SceneBuilder& b, SceneDesc& scene, const SourceLoc& loc, const char* kind) {
    ++scene.skipped_shapes;
    b.warn(loc, std::string("skip:") + kind, std::string(kind) + " skipped");
}

// --missing-textures checker: a loud stand-in, one warning per missing file.
void missing_texture(const SceneBuilder& b, SceneDesc& scene, const SourceLoc& loc,
                     const std::string& path, std::string message) {
    auto& missing = scene.missing_textures;
    if (std::find(missing.begin(), missing.end(), path) != missing.end()) return;
    missing.push_back(path);
    b.warn(loc, "missing-texture:" + path, std::move(message));
}

}  // namespace

// ---- the tree and its files ---------------------------------------------------------------------
void SceneBuilder::set_dialect(Dialect d, std::string top_dir) {
    m_dialect = d;
    m_top_dir = std::move(top_dir);
}

void SceneBuilder::open_file(const File& file) {
    auto& f = *m_open.emplace_back(std::make_unique<OpenFile>());
    f.index = m_scene.files.size();
    f.top = f.index == 0 && !m_copy;
    f.dir = file.dir;
    f.desc.path = file.name;
    f.desc.canonical_path = file.canonical;
    f.stack.push_back(&f.desc.root);
    f.stack_is_joint.push_back(0);
    if (m_dialect == Dialect::V3) f.v3.push_back({});  // the root list
    f.desc.vertices.reserve(file.vertices);
    if (m_dialect != Dialect::V3) f.desc.root.shapes.reserve(file.top_shapes);
    m_scene.files.emplace_back().canonical_path = file.canonical;  // the identity reserved
    if (file.from) {
        m_file->desc.ray_files[file.from->slot] = static_cast<int>(f.index);
        m_include_locs.push_back(file.from->loc);
        f.included = true;
    }
    m_file = &f;
}

void SceneBuilder::close_file(const SourceLoc& eof) {
    OpenFile& f = *m_file;
    const int ntex = static_cast<int>(f.desc.textures.size());
    for (const OpenFile::TextureRef& r : f.texture_refs)
        if (r.index < -1 || r.index >= ntex)
            fail(r.loc, "texture index " + std::to_string(r.index) + " out of range [-1," +
                            std::to_string(ntex) + ")");
    if (m_dialect == Dialect::V3) {
        if (f.v3.size() > 1) fail(eof, v3_open_message(f.v3.back(), "end of file"));
        f.desc.root = std::move(f.v3.back().group);
        f.desc.root.loc = {};
    } else if (f.stack.size() > 1) {
        fail(eof, std::string(f.stack_is_joint.back() ? "#joint_begin" : "#group_begin") + " at " +
                      f.stack.back()->loc.str() + " is never closed");
    }
    for (int k = 0; k < kCountKinds && m_dialect != Dialect::V3; ++k) {
        const Count& c = f.counts[static_cast<size_t>(k)];
        if (c.declared && c.found < c.declared_n)
            fail(eof, std::string(kCountDirective[static_cast<size_t>(k)]) + " at " + c.loc.str() +
                          " declares " + std::to_string(c.declared_n) + ", found " +
                          std::to_string(c.found));
    }
    m_scene.files[f.index] = std::move(f.desc);
    if (f.included) m_include_locs.pop_back();
    m_open.pop_back();
    m_file = m_open.empty() ? nullptr : m_open.back().get();
}

std::optional<SceneBuilder::Include> SceneBuilder::take_include() {
    if (!m_include) return std::nullopt;
    Include inc = std::move(*m_include);
    m_include.reset();
    if (m_copy && !m_copy->piece) {  // numbered in the tree's order, by the merge
        m_copy->includes.push_back({m_diag.warnings().size(), m_scene.tracks.size(), inc});
        return std::nullopt;
    }
    // A file that (transitively) includes itself is an error naming the chain.
    for (size_t i = 0; i < m_open.size(); ++i) {
        if (m_open[i]->desc.canonical_path == inc.canonical) {
            std::string chain;
            for (size_t k = i; k < m_open.size(); ++k)
                chain += fs::path(m_open[k]->desc.path).filename().string() + " -> ";
            chain += fs::path(inc.resolved).filename().string();
            fail(inc.path_loc, "include cycle: " + chain);
        }
    }
    if (m_open.size() >= static_cast<size_t>(kMaxIncludeDepth))
        fail(inc.loc, "#ray_file includes nested deeper than " + std::to_string(kMaxIncludeDepth) +
                          " files");
    for (size_t i = 0; i < m_scene.files.size(); ++i) {
        if (m_scene.files[i].canonical_path == inc.canonical) {
            m_file->desc.ray_files[inc.slot] = static_cast<int>(i);
            return std::nullopt;
        }
    }
    return inc;
}

void SceneBuilder::merge_piece(SceneBuilder& piece, const std::exception_ptr& error) {
    // In file order: what the run's pieces before it added.
    for (const Warning& w : piece.m_diag.warnings())
        for (int n = 0; n < w.count; ++n) m_diag.warn(w.loc, w.kind, w.message, w.included_from);
    m_scene.skipped_shapes += piece.m_scene.skipped_shapes;
    if (error) {
        close_run();
        std::rethrow_exception(error);
    }
    OpenFile& f = *m_file;
    OpenFile& s = *piece.m_file;
    f.graph_started = f.graph_started || s.graph_started;
    f.counts = s.counts;
    // Its range after what the run wrote before it: moved down only where a range before it
    // was written short (a degenerate triangle skipped).
    const auto place = [](auto& to, const auto& from) {
        if (from.first != to.next) std::move(from.first, from.next, to.next);
        to.next += from.next - from.first;
        to.end = to.next;
    };
    if (f.run.vertices)
        place(f.lent_vertices, s.lent_vertices);
    else
        place(f.lent_shapes, s.lent_shapes);
}

namespace {

// The array a run writes: the file's vertices, else the innermost group's or triangle list's
// shapes.
template <class OpenFile>
HugePageVector<ShapeDesc>& run_shapes(OpenFile& f) {
    return f.v3.empty() ? f.stack.back()->shapes : f.v3.back().group.shapes;
}

}  // namespace

void SceneBuilder::open_run(bool vertices, size_t n, size_t own) {
    OpenFile& f = *m_file;
    f.run = {vertices, 0, n, nullptr, nullptr};
    const auto room = [&](auto& array, auto& lent) {
        f.run.at = array.size();
        // Geometric growth still, for a group whose runs come one after another.
        if (f.run.at + n > array.capacity())
            array.reserve(std::max(f.run.at + n, array.capacity() + array.capacity() / 2));
        array.resize(f.run.at + n);
        auto* first = array.data() + f.run.at;
        lent = {first, first, first + own};
        return first;
    };
    if (vertices)
        f.run.vertex_room = room(f.desc.vertices, f.lent_vertices);
    else
        f.run.shape_room = room(run_shapes(f), f.lent_shapes);
}

void SceneBuilder::close_run() {
    OpenFile& f = *m_file;
    const auto close = [&](auto& array, auto& lent) {
        if (lent.first) array.resize(f.run.at + static_cast<size_t>(lent.next - lent.first));
        lent = {};
    };
    if (f.run.vertices)
        close(f.desc.vertices, f.lent_vertices);
    else
        close(run_shapes(f), f.lent_shapes);
    f.run = {};
}

bool SceneBuilder::merge(SceneBuilder& copy, const Include* from, const std::exception_ptr& error) {
    Copy& c = *copy.m_copy;
    if (c.piece) {
        merge_piece(copy, error);
        return false;
    }
    const std::vector<Warning>& warnings = copy.m_diag.warnings();
    if (!c.started) {  // the file opens in the tree, with its description as parsed
        c.started = true;
        open_file({from->resolved, from->canonical, "", from});
        // Its ray files are numbered as the merge reaches them (a failed parse: as far as it
        // came).
        m_file->desc = std::move(error ? copy.m_open.front()->desc : copy.m_scene.files[0]);
        c.track_of.assign(copy.m_scene.tracks.size(), -1);
    }
    // Its warnings (with the include chain) and tracks up to its next #ray_file, or the end.
    const bool more = c.merged < c.includes.size();
    const size_t to_w = more ? c.includes[c.merged].warnings : warnings.size();
    const size_t to_t = more ? c.includes[c.merged].tracks : copy.m_scene.tracks.size();
    const std::vector<SourceLoc> outer(m_include_locs.rbegin(), m_include_locs.rend());
    for (; c.warnings < to_w; ++c.warnings) {
        const Warning& w = warnings[c.warnings];
        if (w.kind.rfind("missing-texture:", 0) == 0) {
            missing_texture(*this, m_scene, w.loc, w.kind.substr(16), w.message);
            continue;
        }
        std::vector<SourceLoc> chain = w.included_from;
        chain.insert(chain.end(), outer.begin(), outer.end());
        for (int n = 0; n < w.count; ++n) m_diag.warn(w.loc, w.kind, w.message, chain);
    }
    for (; c.tracks < to_t; ++c.tracks) {
        c.track_of[c.tracks] = static_cast<int>(m_scene.tracks.size());
        m_scene.tracks.push_back(copy.m_scene.tracks[c.tracks]);
    }
    if (more) {
        m_include = c.includes[c.merged++].include;
        return true;
    }
    if (error) {
        try {
            std::rethrow_exception(error);
        } catch (const SceneError& e) {
            std::vector<SourceLoc> chain = e.included_from();
            chain.insert(chain.end(), outer.begin(), outer.end());
            throw SceneError(e.loc(), e.message(), std::move(chain));
        }
    }
    m_scene.skipped_shapes += copy.m_scene.skipped_shapes;
    // The joints' tracks, numbered in the tree's order.
    std::vector<GroupDesc*> todo = {&m_file->desc.root};
    while (!todo.empty()) {
        GroupDesc* g = todo.back();
        todo.pop_back();
        if (g->track >= 0) g->track = c.track_of[static_cast<size_t>(g->track)];
        for (GroupDesc& sub : g->groups) todo.push_back(&sub);
        for (CsgDesc& csg : g->csgs)
            for (GroupDesc& o : csg.operands) todo.push_back(&o);
    }
    m_scene.files[m_file->index] = std::move(m_file->desc);
    if (m_file->included) m_include_locs.pop_back();
    m_open.pop_back();
    m_file = m_open.empty() ? nullptr : m_open.back().get();
    return false;
}

SceneDesc SceneBuilder::finish() {
    // Instancing multiplies: a file placed k times that instances another m times places it k*m
    // times. The compiler visits every placement, so their number is bounded here, where the
    // instance directives still have their locations.
    std::vector<long long> memo(m_scene.files.size(), -1);
    if (!m_scene.files.empty()) placements(*this, m_scene, 0, memo);
    m_scene.dialect = m_dialect;
    if (!m_scene.camera && !m_scene.files.empty() && !m_all_zero_camera)
        warn({intern_file_name(m_scene.files[0].path), 0, 0}, "no-camera",
             "no #camera: using the default camera");
    return std::move(m_scene);
}

namespace {

// The recursion follows the include tree, which is acyclic and at most kMaxIncludeDepth deep.
long long placements(const SceneBuilder& b, const SceneDesc& scene, size_t fi,
                     std::vector<long long>& memo) {
    if (memo[fi] >= 0) return memo[fi];
    const FileDesc& file = scene.files[fi];
    long long total = 1;  // the file itself
    std::vector<const GroupDesc*> todo = {&file.root};
    while (!todo.empty()) {
        const GroupDesc* g = todo.back();
        todo.pop_back();
        for (const InstanceDesc& in : g->instances) {
            const int sub = file.ray_files[static_cast<size_t>(in.ray_file)];
            total += placements(b, scene, static_cast<size_t>(sub), memo);
            if (total > kMaxPlacements)
                b.fail(in.loc, "instancing places more than " + std::to_string(kMaxPlacements) +
                                   " copies of files (nested instances multiply)");
        }
        for (const GroupDesc& c : g->groups) todo.push_back(&c);
        for (const CsgDesc& c : g->csgs)
            for (const GroupDesc& o : c.operands) todo.push_back(&o);
    }
    return memo[fi] = total;
}

}  // namespace

// ---- counts and the order of a file
// ---------------------------------------------------------------
void SceneBuilder::declare_count(const SourceLoc& loc, CountKind k, int n, const SourceLoc& n_loc,
                                 size_t room) {
    Count& c = m_file->counts[k];
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
    if (k == kVertices) m_file->desc.vertices.reserve(std::min(static_cast<size_t>(n), room));
}

bool SceneBuilder::place(const SourceLoc& loc, std::string_view name, Part part) {
    OpenFile& f = *m_file;
    if (part == Definition) {
        if (f.graph_started) fail(loc, "definition after the scene graph started");
        return false;
    }
    // Spec §13.1: global, then local, then shapes.
    static constexpr std::array<const char*, 3> kPart = {"global", "local", "shapes"};
    const int p = part - Global;
    if (p < f.v3_part) {
        const SourceLoc& start = f.v3_part == 1 ? f.v3_local_start : f.v3_shapes_start;
        fail(loc, quote(name) + " after the " + kPart[static_cast<size_t>(f.v3_part)] +
                      " part started at " + start.str() + " (V3 order: global, local, shapes)");
    }
    if (p == 1 && f.v3_part < 1) f.v3_local_start = loc;
    if (p == 2 && f.v3_part < 2) f.v3_shapes_start = loc;
    f.v3_part = std::max(f.v3_part, p);
    if (part != Shapes) return false;
    // Spec §13.5: the head of #shape_triangles or a CSG node takes only #shape_list_begin, the
    // list of #shape_triangles only triangles.
    V3Frame& top = f.v3.back();
    if (top.kind == V3Frame::TrianglesHead || top.kind == V3Frame::CsgHead) {
        if (name != "#shape_list_begin") fail(loc, v3_open_message(top, quote(name)));
        top.kind = top.kind == V3Frame::TrianglesHead ? V3Frame::Triangles : V3Frame::CsgList;
        return true;
    }
    if (top.kind == V3Frame::Triangles && name != "#shape_triangle" && name != "#shape_list_end")
        fail(loc, quote(name) + " inside the list of #shape_triangles at " + top.loc.str() +
                      " (only #shape_triangle may be there)");
    if (name == "#shape_triangle" && top.kind != V3Frame::Triangles)
        fail(loc, "#shape_triangle outside #shape_triangles");
    return false;
}

// ---- paths --------------------------------------------------------------------------------------
// Spec §4.2: relative to the naming file's directory, then the working directory. V3 (spec
// §13.2): the top-level file's directory first, then those two with a warning.
std::optional<std::string> SceneBuilder::resolve(const SourceLoc& at, const std::string& path,
                                                 const std::string& what,
                                                 std::string* tried) const {
    std::string places;  // those tried; a directory of that name is said so, not left to look
                         // missing
    const fs::path p(path);
    std::optional<std::string> found;
    if (p.is_absolute()) {
        places = is_dir(p) ? path + " (a directory)" : "";
        if (is_file(p)) found = path;
    } else {
        const bool v3 = m_dialect == Dialect::V3;
        std::vector<fs::path> unique;
        std::vector<fs::path> candidates;
        if (v3) candidates.push_back(fs::path(m_top_dir) / p);
        candidates.push_back(fs::path(m_file->dir) / p);
        candidates.push_back(fs::path(".") / p);
        for (const fs::path& c : candidates)
            if (std::find_if(unique.begin(), unique.end(), [&](const fs::path& u) {
                    return u.lexically_normal() == c.lexically_normal();
                }) == unique.end())
                unique.push_back(c);
        for (size_t i = 0; i < unique.size() && !found; ++i) {
            if (!is_file(unique[i])) continue;
            found = unique[i].lexically_normal().string();
            if (v3 && i > 0)
                warn(at, "v3-path:" + path,
                     quote(path) + " found as " + *found + ", not in " + m_top_dir +
                         " (V3 resolves paths against the top-level file's directory)");
        }
        for (const fs::path& c : unique)
            if (!found)
                places +=
                    (places.empty() ? "" : ", ") + c.string() + (is_dir(c) ? " (a directory)" : "");
    }
    if (found || tried) {
        if (tried) *tried = places;
        return found;
    }
    if (places.empty()) fail(at, "cannot open " + what + " " + quote(path));
    fail(at, "cannot open " + what + " " + quote(path) + " (tried " + places + ")");
}

// ---- camera, lights, the global settings --------------------------------------------------------
namespace {

// What is wrong with a camera, or "".
std::string camera_problem(const CameraDesc& c) {
    if (glm::length(c.direction) == 0.0) return "camera view direction is zero";
    if (glm::length(c.up) == 0.0) return "camera up vector is zero";
    if (glm::length(glm::cross(glm::normalize(c.direction), glm::normalize(c.up))) < 1e-6)
        return "camera up vector is parallel to the view direction";
    if (!(c.half_height_angle_rad > 0.0 && c.half_height_angle_rad < kPi / 2))
        return "camera half-height angle " + fmt(c.half_height_angle_rad) +
               " is outside (0, pi/2) radians";
    return "";
}

bool all_zero(const CameraDesc& c) {
    return c.position == Vec3(0.0) && c.direction == Vec3(0.0) && c.up == Vec3(0.0) &&
           c.half_height_angle_rad == 0.0;
}

}  // namespace

void SceneBuilder::camera(const CameraDesc& c) {
    // Included files: syntax only, so the dummy all-zero cameras of sub-files pass (§3.1, §12).
    if (!m_file->top) return;
    // The course's V3 sub-files without a V3 marker read as V1 (§10 step 4), and opened on their
    // own they should render as V3 ones do (§13.3): the dummy camera (never a valid camera) is
    // the default camera with a warning in every dialect.
    const bool v3 = m_dialect == Dialect::V3;
    if (v3 && m_camera_loc.file)  // spec §13.3: the last #camera wins
        warn(
            c.loc, "camera-repeat",
            "second #camera: the last one wins (the earlier one is at " + m_camera_loc.str() + ")");
    if (v3) m_camera_loc = c.loc;
    if ((v3 || !m_scene.camera) && all_zero(c)) {
        warn(c.loc, "camera-zero",
             "all-zero #camera (a sub-file's dummy): using the default camera");
        m_all_zero_camera = true;
        m_scene.camera.reset();
        return;
    }
    if (const std::string problem = camera_problem(c); !problem.empty()) fail(c.loc, problem);
    if (!v3 && m_scene.camera) {  // V0/V1: the first one wins
        warn(c.loc, "camera-repeat",
             "second #camera ignored; the first one (" + m_scene.camera->loc.str() + ") wins");
        return;
    }
    m_scene.camera = c;
}

void SceneBuilder::global_colour(bool background, const SourceLoc& loc, const Vec3& c) {
    if (!m_file->top) return;  // included files: syntax only
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

void SceneBuilder::spot(LightDesc& l, const SourceLoc& cutoff_loc,
                        const SourceLoc& dropoff_loc) const {
    if (glm::length(l.direction) == 0.0) fail(l.loc, "spot light direction is zero");
    if (l.cutoff_rad < 0) fail(cutoff_loc, "negative spot cutoff " + fmt(l.cutoff_rad));
    if (l.spot_exponent < 0) fail(dropoff_loc, "negative spot drop-off " + fmt(l.spot_exponent));
    // p = 128 dor (V0, as a material's kspec) or dor (V1, V3).
    if (m_dialect == Dialect::V0) l.spot_exponent *= kV0ExponentScale;
    if (l.cutoff_rad > kPi / 2)
        warn(l.loc, "spot-cutoff",
             "spot cutoff " + fmt(l.cutoff_rad) +
                 " rad is more than pi/2: the light never cuts off");
}

void SceneBuilder::light(const LightDesc& l) {
    if (m_dialect != Dialect::V3) count_item(l.loc, kLights);
    OpenFile& f = *m_file;
    if (!f.top) {
        // V3 warns once per file.
        if (m_dialect != Dialect::V3 || !f.warned_included_light)
            warn(l.loc, "included-light", "lights in included files are ignored");
        f.warned_included_light = true;
        return;
    }
    m_scene.lights.push_back(l);
}

void SceneBuilder::shader(std::string vertex, std::string fragment) {
    if (!m_file->top) return;  // spec §13.3: recorded (the last one wins), never opened
    m_scene.shader_vertex = std::move(vertex);
    m_scene.shader_fragment = std::move(fragment);
}

// ---- definitions --------------------------------------------------------------------------------
void SceneBuilder::texture(const SourceLoc& loc, const SourceLoc& path_loc,
                           const std::string& path) {
    TextureDesc t;
    t.loc = loc;
    std::string tried, problem;
    const std::optional<std::string> found = resolve(path_loc, path, "texture", &tried);
    if (found) {
        t.path = *found;
        const TextureCache::Decoded decoded = m_textures->decode(t.path);
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
        missing_texture(*this, m_scene, path_loc, path, problem + "; a checker stands in");
    }
    m_file->desc.textures.push_back(std::move(t));
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

void SceneBuilder::add_material(MaterialDesc m, const SourceLoc& texture_loc) {
    // Definitions may come in any order: the range is checked at the end of the file.
    m_file->texture_refs.push_back({texture_loc, m.texture});
    m_file->desc.materials.push_back(std::move(m));
}

void SceneBuilder::vertex(VertexDesc v) {
    const double len = glm::length(v.normal);
    if (len > 0) v.normal /= len;
    auto& lent = m_file->lent_vertices;  // a mesh run's range, written in place
    if (lent.next != lent.end)
        *lent.next++ = v;
    else
        m_file->desc.vertices.push_back(v);
}

void SceneBuilder::ray_file(const SourceLoc& loc, const SourceLoc& path_loc,
                            const std::string& path) {
    const std::string resolved = *resolve(path_loc, path, "ray file", nullptr);
    m_include =
        Include{loc, path_loc, resolved, canonical_path(resolved), m_file->desc.ray_files.size()};
    m_file->desc.ray_files.push_back(-1);  // numbered when its file is (take_include)
}

void SceneBuilder::key_file(const SourceLoc& loc, const SourceLoc& path_loc,
                            const std::string& path) {
    const std::string resolved = *resolve(path_loc, path, "key file", nullptr);
    std::string text, why;
    if (!read_file(resolved, &text, &why))
        fail(path_loc, read_failure("cannot read key file", resolved, why));
    m_include_locs.push_back(loc);
    m_file->key_files.push_back(parse_key_file(*this, text, resolved, m_dialect == Dialect::V3));
    m_file->key_files.back().named = path;
    m_file->desc.key_files.push_back(resolved);
    m_include_locs.pop_back();
}

// ---- the scene graph ----------------------------------------------------------------------------
int SceneBuilder::material_index(const SourceLoc& loc, int m) const {
    const int n = static_cast<int>(m_file->defs->materials.size());
    const bool v0_default = (m == -1 && m_dialect == Dialect::V0);
    if (!v0_default && (m < 0 || m >= n)) {
        std::string msg = "material index " + std::to_string(m) + " out of range [" +
                          (m_dialect == Dialect::V0 ? "-1," : "0,") + std::to_string(n) + ")";
        if (m == -1) msg += " (-1 is V0 only; try --dialect v0)";
        fail(loc, msg);
    }
    return m;
}

void SceneBuilder::vertex_index(const SourceLoc& loc, int v) const {
    const int nv = static_cast<int>(m_file->defs->vertices.size());
    if (v < 0 || v >= nv)
        fail(loc,
             "vertex index " + std::to_string(v) + " out of range [0," + std::to_string(nv) + ")");
}

namespace {

void deliver(const SceneBuilder& b, std::vector<V3Frame>& frames, int& csg_depth,
             std::optional<V3Node> node);

}  // namespace

void SceneBuilder::shape(ShapeDesc&& s, const char* empty) {
    OpenFile& f = *m_file;
    const bool triangle_list = !f.v3.empty() && f.v3.back().kind == V3Frame::Triangles;
    if (triangle_list) s.material = f.v3.back().material;
    f.graph_started = true;
    const auto* t = std::get_if<TriangleDesc>(&s.geometry);
    const char* skip = t && degenerate_triangle(*f.defs, *t) ? "degenerate triangle" : empty;
    if (skip) skip_shape(*this, m_scene, s.loc, skip);
    auto& lent = f.lent_shapes;  // a mesh run's range, written in place
    if (!skip && lent.next != lent.end && (triangle_list || f.v3.empty())) {
        *lent.next++ = std::move(s);
    } else if (triangle_list) {
        if (!skip) f.v3.back().group.shapes.push_back(std::move(s));
    } else if (!f.v3.empty()) {
        V3Node node;
        node.loc = s.loc;
        node.kind = skip ? V3Node::Empty : V3Node::Shape;
        if (!skip) node.shape = std::move(s);
        deliver(*this, f.v3, f.v3_csg_depth, std::move(node));
    } else if (!skip) {
        f.stack.back()->shapes.push_back(std::move(s));
    }
}

void SceneBuilder::instance(const SourceLoc& loc, const SourceLoc& index_loc, int i) {
    OpenFile& f = *m_file;
    f.graph_started = true;
    const int n = static_cast<int>(f.desc.ray_files.size());
    if (i < 0 || i >= n)
        fail(index_loc,
             "ray file index " + std::to_string(i) + " out of range [0," + std::to_string(n) + ")");
    if (f.v3.empty()) return f.stack.back()->instances.push_back({loc, i});
    V3Node node;
    node.kind = V3Node::Instance;
    node.loc = loc;
    node.instance = {loc, i};
    deliver(*this, f.v3, f.v3_csg_depth, std::move(node));
}

namespace {

// Spec §14.2: the DOF `name` among the file's key files (the first that has it wins; an exact
// match first, else one ignoring ASCII case, with a warning): its key file and index.
std::pair<KeyFile*, size_t> find_dof(const SceneBuilder& b, std::vector<KeyFile>& key_files,
                                     const SourceLoc& name_loc, const std::string& name) {
    KeyFile* hit = nullptr;
    size_t dof = 0;
    const std::string key = lower(name);
    for (KeyFile& k : key_files) {
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
            b.warn(name_loc, "dof-repeat",
                   "DOF " + quote(k.names[here]) + " is also in " + quote(k.named) +
                       "; the first key file (" + quote(hit->named) + ") wins");
            continue;
        }
        if (similar.size() > 1) {
            std::string list;
            for (size_t s : similar) list += (list.empty() ? "" : ", ") + quote(k.names[s]);
            b.fail(name_loc, "joint " + quote(name) + " matches several DOFs of " + quote(k.named) +
                                 " when case is ignored: " + list);
        }
        hit = &k, dof = similar.empty() ? here : similar.front();
    }
    if (!hit) {
        std::string names;
        for (const KeyFile& k : key_files) names += (names.empty() ? "" : ", ") + k.named;
        b.fail(name_loc, "no DOF " + quote(name) + " in key files " + names);
    }
    if (hit->names[dof] != name)
        b.warn(name_loc, "joint-case",
               "joint " + quote(name) + " matches DOF " + quote(hit->names[dof]) +
                   " only when case is ignored");
    return {hit, dof};
}

}  // namespace

void SceneBuilder::open(const Construct& c) {
    OpenFile& f = *m_file;
    const std::string directive(c.directive);
    GroupDesc g;
    g.loc = c.loc;
    g.matrix = c.matrix;
    if (c.kind == Construct::Group || c.kind == Construct::Joint) {
        f.graph_started = true;
        if (f.stack.size() > static_cast<size_t>(kMaxGroupDepth))
            fail(c.loc, directive + " nests groups deeper than " + std::to_string(kMaxGroupDepth) +
                            " levels");
    }
    if (c.kind == Construct::Group) check_matrix(*this, c.matrix, c.loc, "group matrix");
    if (c.kind == Construct::Affine) check_matrix(*this, c.matrix, c.loc, "#static_affine matrix");
    if (c.kind == Construct::Joint || c.kind == Construct::Dynamic) {
        // Spec §4.4, §14.2: the DOF of that name in the file's key files, key 0 as read.
        g.joint = c.name;
        const bool joint = c.kind == Construct::Joint;
        bool& warned = joint ? f.warned_joint_identity : f.warned_dynamic_identity;
        if (f.key_files.empty()) {
            if (!warned)
                warn(c.loc, "joint-no-key",
                     joint ? "no #key_file: joints use the identity"
                           : "no #key_file: #dynamic_affine uses the identity");
            warned = true;
        } else {
            auto [key, dof] = find_dof(*this, f.key_files, c.name_loc, c.name);
            int& track = key->track[dof];
            if (track < 0) {
                track = static_cast<int>(m_scene.tracks.size());
                KeyTrack t;
                t.name = key->names[dof];
                t.duration = key->duration;
                t.keys = key->keys[dof];
                t.loc = c.name_loc;
                m_scene.tracks.push_back(std::move(t));
            }
            g.track = track;
            g.matrix = m_scene.tracks[static_cast<size_t>(track)].keys[0];
        }
    }
    if (c.kind == Construct::Group || c.kind == Construct::Joint) {
        GroupDesc* parent = f.stack.back();
        parent->groups.push_back(std::move(g));
        f.stack.push_back(&parent->groups.back());
        f.stack_is_joint.push_back(c.kind == Construct::Joint);
        return;
    }
    // A V3 construct, within the nesting limits (no consumer recurses deeper than them).
    if (f.v3.size() > static_cast<size_t>(kMaxV3Depth))
        fail(c.loc, quote(c.directive) + " nests V3 shapes deeper than " +
                        std::to_string(kMaxV3Depth) + " levels");
    const bool csg = c.kind == Construct::Csg || c.kind == Construct::Difference;
    if (csg && f.v3_csg_depth >= kMaxCsgDepth)
        fail(c.loc, quote(c.directive) + " nests CSG nodes deeper than " +
                        std::to_string(kMaxCsgDepth) + " levels");
    if (csg) ++f.v3_csg_depth;
    static constexpr std::array<V3Frame::Kind, 8> kFrame = {
        V3Frame::Root,   V3Frame::Root,          V3Frame::List,    V3Frame::Affine,
        V3Frame::Affine, V3Frame::TrianglesHead, V3Frame::CsgHead, V3Frame::Difference};
    V3Frame fr;
    fr.kind = kFrame[c.kind];
    fr.loc = c.loc;
    fr.name = directive;
    fr.group = std::move(g);
    fr.csg.loc = c.loc;
    fr.csg.op = c.op;
    fr.material = c.material;
    f.v3.push_back(std::move(fr));
}

void SceneBuilder::close(const SourceLoc& loc, std::string_view directive) {
    OpenFile& f = *m_file;
    if (!f.v3.empty()) {  // #shape_list_end: the innermost construct is finished
        const V3Frame& top = f.v3.back();
        if (top.kind == V3Frame::Root) fail(loc, "#shape_list_end without #shape_list_begin");
        if (top.kind == V3Frame::Affine || top.kind == V3Frame::Difference)
            fail(loc, v3_open_message(top, "#shape_list_end"));
        return deliver(*this, f.v3, f.v3_csg_depth, {});
    }
    f.graph_started = true;
    const bool joint = directive == "#joint_end";
    const std::string name(directive);
    if (f.stack.size() <= 1 || (f.stack_is_joint.back() != 0) != joint) {
        if (f.stack.size() > 1)
            fail(loc, name + " does not match " +
                          (f.stack_is_joint.back() ? "#joint_begin" : "#group_begin") + " at " +
                          f.stack.back()->loc.str());
        fail(loc, name + " without " + (joint ? "#joint_begin" : "#group_begin"));
    }
    f.stack.pop_back();
    f.stack_is_joint.pop_back();
}

// ---- the constructs of a V3 shapes part ---------------------------------------------------------
namespace {

// What an unfinished construct still needs, for the error at `what` (a directive or the end of
// the file).
std::string v3_open_message(const V3Frame& fr, const std::string& what) {
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

V3Node finished(const SceneBuilder& b, int& csg_depth, V3Frame& fr) {
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
            --csg_depth;
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
// (a transform after its one shape, a difference after its second). No node: the innermost
// construct is finished (#shape_list_end).
void deliver(const SceneBuilder& b, std::vector<V3Frame>& frames, int& csg_depth,
             std::optional<V3Node> node) {
    for (;;) {
        if (node) {
            V3Frame& to = frames.back();
            receive(to, *node);
            const bool done = (to.kind == V3Frame::Affine && to.has_child) ||
                              (to.kind == V3Frame::Difference && to.csg.operands.size() == 2);
            if (!done) return;
        }
        V3Frame fr = std::move(frames.back());
        frames.pop_back();
        node = finished(b, csg_depth, fr);
    }
}

bool degenerate_triangle(const FileDesc& file, const TriangleDesc& t) {
    // Spec §3.3: a repeated index, or |e1 x e2| <= 1e-12 |e1| |e2|.
    if (t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[0] == t.v[2]) return true;
    const Vec3& p0 = file.vertices[static_cast<size_t>(t.v[0])].position;
    const Vec3 e1 = file.vertices[static_cast<size_t>(t.v[1])].position - p0;
    const Vec3 e2 = file.vertices[static_cast<size_t>(t.v[2])].position - p0;
    return glm::length(glm::cross(e1, e2)) <= 1e-12 * glm::length(e1) * glm::length(e2);
}

// Spec §3.3 / §4.1: affine (bottom row 0 0 0 1) and non-singular.
void check_matrix(const SceneBuilder& b, const Mat4& m, const SourceLoc& loc,
                  const std::string& what) {
    if (std::abs(m[0][3]) > 1e-9 || std::abs(m[1][3]) > 1e-9 || std::abs(m[2][3]) > 1e-9 ||
        std::abs(m[3][3] - 1.0) > 1e-9)
        b.fail(loc, "projective " + what + ": the bottom row must be 0 0 0 1");
    const Mat3 a(m);
    if (!std::isfinite(glm::determinant(a)) ||
        !std::isfinite(std::hypot(a[0].x, a[0].y, a[0].z) * std::hypot(a[1].x, a[1].y, a[1].z) *
                       std::hypot(a[2].x, a[2].y, a[2].z)))
        b.fail(loc, what + " too large: its determinant overflows");
    if (singular_3x3(a)) b.fail(loc, "singular " + what);
}

}  // namespace

}  // namespace rt::parser_impl
