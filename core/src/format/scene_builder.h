// What the .ray grammar walks build, and what it means: the one SceneBuilder of a parse holds
// the scene description under construction and every rule that is not syntax (which camera
// wins, where a path is found, a material's numbers by dialect, the range of an index, the
// groups of a file, the includes and their cycles, the key files and the DOFs bound to them),
// with the include chain that every error and warning carries. The grammar walks (grammar.h)
// read tokens and call it with values and the file:line:col of each; it never sees a token.
// Private to core/src/format.
#pragma once

#include <array>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "format/parser_impl.h"

namespace rt::parser_impl {

/// The numbers of a #material as read, before the dialect gives them their meaning: up to 18,
/// each with its place (the last, the texture index, read again as an integer).
struct MaterialNumbers {
    SourceLoc loc;  // the directive
    std::array<double, 18> v{};
    std::array<SourceLoc, 18> at{};
    int n = 0;         // 16 (V0) or 18 (V1, V3)
    std::string name;  // between the !…!
};

/// An included file parsed ahead, on a thread of its own, before the walk of the tree reaches
/// its #ray_file (Parser::parse_ahead): its description, and what it did whose place in the
/// tree's order only that walk knows, in the order it did it, to be replayed there
/// (SceneBuilder::replay): its warnings, its own #ray_file directives (whose files are numbered
/// and parsed then), the key tracks it made, the missing textures it stood checkers in for.
struct Ahead {
    struct Event {
        enum Kind { Warning, Include, Track, MissingTexture } what = Warning;
        SourceLoc loc;  // Warning, MissingTexture: the warning's; Include: the directive's
        std::string kind, message;     // Warning, MissingTexture (the warning's)
        std::vector<SourceLoc> chain;  // Warning: the key file it was in, if any
        SourceLoc path_loc;            // Include
        std::string path, resolved;    // Include: as written and found; MissingTexture: path
        size_t index = 0;              // Include: its slot in desc.ray_files; Track: the track
    };
    std::string name;  // the path the pre-scan found it as (the walk must name it the same)
    std::string canonical;
    std::vector<Event> events;
    std::exception_ptr error;  // what stopped its parse, after the events
    FileDesc desc;
    std::vector<KeyTrack> tracks;  // Track events index these
    size_t skipped = 0;
};

/// Textures decoded once per scene, shared by the builders of files parsed ahead.
struct TextureCache {
    struct Decoded {
        std::shared_ptr<const TextureImage> image;  // null when it does not decode
        std::string error;
    };
    std::mutex mutex;
    std::map<std::string, Decoded> decoded;  // by canonical path
    uint64_t texels = 0;                     // of every texture decoded (max_scene_texels())
};

class SceneBuilder {
public:
    SceneBuilder(Diagnostics& diag, const ParseOptions& options)
        : m_diag(diag), m_options(options), m_textures(std::make_shared<TextureCache>()) {}
    /// The builder of a file parsed ahead for `tree`'s (its events and description into *out).
    SceneBuilder(const SceneBuilder& tree, Ahead* out)
        : m_diag(tree.m_diag),
          m_options(tree.m_options),
          m_dialect(tree.m_dialect),
          m_v3_marker(tree.m_v3_marker),
          m_top_dir(tree.m_top_dir),
          m_textures(tree.m_textures),
          m_ahead(out) {}

    // ---- errors and warnings: with the include chain as notes ----------------------------
    [[noreturn]] void fail(const SourceLoc& loc, const std::string& message) const;
    /// On a thread parsing a piece of a run, warnings wait in its PieceOutput, so they reach
    /// the diagnostics in file order.
    void warn(const SourceLoc& loc, std::string kind, std::string message) const;
    /// A warning a piece of a run kept, handed on in file order.
    void warn(PieceOutput::Pending&& w) const;
    /// A degenerate shape left out, with its warning ("degenerate triangle skipped").
    void skip_shape(const SourceLoc& loc, const char* kind);
    /// Where the warnings and skipped shapes of this thread go (a piece of a run), or null.
    static inline thread_local PieceOutput* t_piece = nullptr;

    // ---- the tree as a whole ----------------------------------------------------------------
    Dialect dialect() const { return m_dialect; }
    /// The dialect the pre-scan settled, the first V3 marker (for messages) and the top-level
    /// file's directory (V3 paths, spec §13.2).
    void set_dialect(Dialect d, std::string v3_marker, std::string top_dir);
    const std::string& v3_marker() const { return m_v3_marker; }
    Diagnostics& diagnostics() const { return m_diag; }
    SceneDesc& scene() { return m_scene; }
    /// The driver's file loop, which #ray_file calls: whether an included file can be read
    /// (why not), and its parse into m_scene.files[index].
    struct FileLoop {
        virtual bool readable(const std::string& resolved, const std::string& canonical,
                              std::string* why) = 0;
        virtual void parse(const std::string& resolved, const std::string& canonical,
                           int index) = 0;

    protected:
        ~FileLoop() = default;
    };
    void set_file_loop(FileLoop* loop) { m_files = loop; }
    /// A file's parse starts or ends (include cycles are found among the open ones).
    void open_file(const std::string& canonical, const std::string& name);
    void close_file() { m_open.pop_back(); }
    /// The end of a V0/V1 file: open groups and counts short of their declaration are errors.
    void end_of_v1_file(FileState& f, const SourceLoc& eof);
    /// Every texture index of the file's materials within its textures (checked at its end:
    /// definitions may come in any order).
    void check_texture_refs(const FileState& f) const;
    /// The tree parsed: placements bounded, the missing-camera warning. The description.
    SceneDesc finish();

    // ---- counts (#*_num, spec §3.1) ----------------------------------------------------------
    /// `n` at n_loc declares the count; `room` bounds what it may reserve (the text left / 24).
    void declare_count(FileState& f, const SourceLoc& loc, CountKind k, int n,
                       const SourceLoc& n_loc, size_t room);
    void count_item(FileState& f, const SourceLoc& loc, CountKind k) const {
        Count& c = f.counts[k];
        ++c.found;
        if (c.declared && c.found > c.declared_n) too_many(loc, k, c);
    }
    /// V0/V1: no definition once the scene graph started (graph(): a group, an instance or a
    /// shape starts it).
    void definition(const FileState& f, const SourceLoc& loc) const {
        if (f.graph_started) fail(loc, "definition after the scene graph started");
    }
    void graph(FileState& f) const { f.graph_started = true; }

    // ---- definitions ---------------------------------------------------------------------
    /// #camera of either dialect: included files' cameras are syntax only; V0/V1 keep the
    /// first, V3 the last; the all-zero one is the default camera.
    void camera(const FileState& f, const CameraDesc& c);
    void global_colour(const FileState& f, bool background, const SourceLoc& loc, const Vec3& c);
    /// The warnings of a light's attenuation (all zero: it never contributes) and of a spot's
    /// cutoff (beyond pi/2: it never cuts off), as the grammar reads them.
    void attenuation(const LightDesc& l) const;
    void spot_cutoff(const LightDesc& l) const;
    /// A light as read: kept (top-level files) or ignored with a warning.
    void light(FileState& f, const LightDesc& l);
    void shader(const FileState& f, std::string vertex, std::string fragment);
    void texture(FileState& f, const SourceLoc& loc, const SourceLoc& path_loc,
                 const std::string& path);
    /// What a #material's numbers mean in the tree's dialect, each checked (the texture index
    /// aside); then the material with its texture index, whose range is checked at the end of
    /// the file.
    MaterialDesc material(const MaterialNumbers& m) const;
    void add_material(FileState& f, MaterialDesc m, const SourceLoc& texture_loc) const;
    void vertex(FileState& f, const SourceLoc& loc, VertexDesc v) const;  // normal made unit
    /// #ray_file: the file's index in the scene, parsed now when it is new (parsed ahead: a
    /// slot in f's ray files that the replay fills).
    void ray_file(FileState& f, const SourceLoc& loc, const SourceLoc& path_loc,
                  const std::string& path);
    /// A file parsed ahead, where the walk of the tree reaches it as file `index` (whose
    /// #ray_file pushed the include chain): its events in order, its files included, its tracks
    /// numbered in the tree's, its error (with the chain); then its description in its place.
    void replay(Ahead& a, int index);
    void key_file(FileState& f, const SourceLoc& loc, const SourceLoc& path_loc,
                  const std::string& path);
    /// The track (index into the scene's tracks) of DOF `name` of f's key files (spec §14.2).
    int bind_dof(FileState& f, const SourceLoc& name_loc, const std::string& name);

    // ---- the scene graph -----------------------------------------------------------------
    /// A material index of a shape (V0's -1 the default material), checked.
    int material_index(const FileState& f, const SourceLoc& loc, int m) const;
    /// A ray file index of an instance, checked.
    void instance_index(const FileState& f, const SourceLoc& loc, int i) const;
    /// A vertex index of a triangle, checked against the file's vertices.
    void vertex_index(const FileState& f, const SourceLoc& loc, int v) const {
        if (v < 0 || static_cast<size_t>(v) >= f.defs().vertices.size())
            vertex_out_of_range(f, loc, v);
    }
    static bool degenerate_triangle(const FileDesc& file, const TriangleDesc& t);
    /// Whether a shape as read is kept: a degenerate triangle, or an analytic shape with a size
    /// of 0 (`empty`, its T::kEmpty, when one is), is skipped with a warning (spec §3.3).
    bool keep_shape(const FileState& f, const ShapeDesc& s, const char* empty = nullptr);
    /// A vertex into the file, or a shape into group list `to`, or into the slots of a piece of
    /// a run (mesh_runs.cpp).
    void add_vertex(FileState& f, const SourceLoc& loc, const VertexDesc& v) const {
        if (!f.vertex_slots.next) return f.desc.vertices.push_back(v);
        if (f.vertex_slots.next == f.vertex_slots.end) fail(loc, kRunOverflow);
        *f.vertex_slots.next++ = v;
    }
    void add_shape(FileState& f, HugePageVector<ShapeDesc>& to, ShapeDesc&& s) const {
        if (!f.shape_slots.next) return to.push_back(std::move(s));
        if (f.shape_slots.next == f.shape_slots.end) fail(s.loc, kRunOverflow);
        *f.shape_slots.next++ = std::move(s);
    }
    static constexpr const char* kRunOverflow =
        "internal error: a mesh run longer than the pre-scan found";
    /// V0/V1: a shape into the innermost open group.
    void group_shape(FileState& f, ShapeDesc&& s) const {
        add_shape(f, f.stack.back()->shapes, std::move(s));
    }
    /// The V0/V1 groups: a #group_begin matrix, a #joint_begin DOF, their ends, an instance.
    void group_begin(FileState& f, const SourceLoc& loc, const std::string& directive,
                     const Mat4& m);
    void joint_begin(FileState& f, const SourceLoc& loc, const std::string& directive,
                     const SourceLoc& name_loc, const std::string& name);
    void group_end(FileState& f, const SourceLoc& loc, const std::string& directive, bool joint);
    void instance(FileState& f, const SourceLoc& loc, const SourceLoc& index_loc, int i);
    /// A #dynamic_affine's DOF (V3): its track, or -1 with a warning when the file has no key
    /// files; the matrix key 0.
    int dynamic_dof(FileState& f, const SourceLoc& loc, const SourceLoc& name_loc,
                    const std::string& name);
    // The V3 shapes part (spec §13.5): its open constructs (FileState::v3), on an explicit
    // stack so that deep nesting never recurses; a finished shape goes to the innermost one,
    // and every construct it completes (a transform after its one shape, a difference after its
    // second) goes to the one below, folded as scene_desc.h says.
    /// Opens a construct at a directive, within the nesting limits.
    V3Frame& v3_open(FileState& f, const SourceLoc& loc, std::string_view directive,
                     V3Frame::Kind kind) const;
    void v3_deliver(FileState& f, V3Node node) const;
    /// #shape_list_end: the innermost construct is finished.
    void v3_close(FileState& f) const;
    /// The end of a V3 file: a construct left open is an error; the root list is the file's.
    void v3_end_of_file(FileState& f, const SourceLoc& eof) const;
    /// What an unfinished construct still needs, for the error at `what` (a directive or the
    /// end of the file).
    static std::string v3_open_message(const V3Frame& fr, const std::string& what);
    /// Affine, non-singular (spec §3.3, §4.1).
    void check_matrix(const Mat4& m, const SourceLoc& loc, const std::string& what) const;

    /// For messages: a number as C++ streams write it.
    static std::string fmt(double v);

private:
    [[noreturn]] void too_many(const SourceLoc& loc, CountKind k, const Count& c) const;
    [[noreturn]] void vertex_out_of_range(const FileState& f, const SourceLoc& loc, int v) const;
    std::optional<std::string> try_resolve(const FileState& f, const SourceLoc& at,
                                           const std::string& path, std::string* tried) const;
    std::string resolve(const FileState& f, const SourceLoc& at, const std::string& path,
                        const std::string& what) const;
    bool dummy_camera(const CameraDesc& c);
    void check_camera(const CameraDesc& c) const;
    long long placements(size_t fi, std::vector<long long>& memo) const;

    // A texture file is decoded once per scene, however many #texture lines (in however many
    // files) name it: every naming shares the image, or the error.
    TextureCache::Decoded decode_once(const std::string& path);
    /// The include of a file found as `resolved`: its cycle, the depth, its index (parsed now
    /// when it is new).
    int include(const SourceLoc& loc, const SourceLoc& path_loc, const std::string& resolved);
    /// A texture missing (a checker stands in): one warning per file named.
    void missing_texture(const SourceLoc& loc, const std::string& path, std::string message);

    struct Open {
        std::string canonical;
        std::string name;
    };

    Diagnostics& m_diag;
    ParseOptions m_options;
    SceneDesc m_scene;
    Dialect m_dialect = Dialect::V1;
    std::string m_v3_marker;      // "'#static_affine' at F:L:C", for messages
    std::string m_top_dir = ".";  // directory of the top-level file (V3 paths, spec §13.2)
    FileLoop* m_files = nullptr;
    std::vector<SourceLoc> m_include_locs;  // #ray_file/#key_file, outermost first
    std::vector<Open> m_open;               // the files being parsed, outermost first
    std::shared_ptr<TextureCache> m_textures;
    Ahead* m_ahead = nullptr;  // this builder's file is parsed ahead: its events go here
    bool m_seen_background = false, m_seen_ambient = false;
    SourceLoc m_camera_loc;          // V3: the last top-level #camera
    bool m_all_zero_camera = false;  // the top-level file's camera is the dummy
};

}  // namespace rt::parser_impl
