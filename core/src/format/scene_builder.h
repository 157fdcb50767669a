// What the .ray grammar walks build, and what it means: the one SceneBuilder of a parse holds
// the scene description under construction and every rule that is not syntax (which camera
// wins, where a path is found, a material's numbers by dialect, the range of an index, the
// groups of a file, the rules of an include, the key files and the DOFs bound to them), with
// the include chain that every error and warning carries. It owns the meaning state of each
// open file (open_file / close_file); the grammar walks (grammar.h) read tokens and call it with
// values and the file:line:col of each, as `b.texture(loc, path_loc, path)`; it never sees a
// token. The driver (driver.h) keeps the texts and the include stack: a #ray_file is handed back
// to it (take_include). A file parsed ahead, or a piece of a mesh run, is parsed into a copy of
// the builder (the copy constructor) whose result the tree's builder merges in the tree's order.
// Private to core/src/format.
#pragma once

#include <array>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
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

class SceneBuilder {
public:
    /// A #ray_file whose file the driver parses (take_include).
    struct Include {
        SourceLoc loc, path_loc;  // the directive, its path
        std::string resolved;     // the path found
        std::string canonical;
        size_t slot = 0;  // its place in the including file's ray files
    };
    /// A file opened: its names and directory; the #ray_file that includes it (none: the
    /// top-level file, or the file of a copy); the room the pre-scan found it needs.
    struct File {
        std::string name, canonical, dir;
        const Include* from = nullptr;
        size_t vertices = 0, top_shapes = 0;
    };
    /// A copy for a piece of a mesh run: a run of #vertex (else of #shape_triangle), the index
    /// in the run of the piece's first directive, and its number of directives, whose vertices
    /// or shapes it writes in place into the room its file made for the run (open_run).
    struct Piece {
        bool vertices = false;
        size_t index = 0, count = 0;
    };
    /// What a grammar walk opens: a V0/V1 #group_begin (its matrix) or #joint_begin (its DOF);
    /// a V3 list, #static_affine (its matrix), #dynamic_affine (its DOF), #shape_triangles (its
    /// material) or CSG node (its operation: a #shape_difference takes no list).
    struct Construct {
        enum Kind { Group, Joint, List, Affine, Dynamic, Triangles, Csg, Difference };
        Kind kind = Group;
        SourceLoc loc;
        std::string_view directive;
        Mat4 matrix{1.0};
        SourceLoc name_loc{};
        std::string name{};
        int material = 0;
        CsgOp op = CsgOp::Union;
    };
    /// Where in a file a directive may come: V0/V1 definitions (none once the scene graph
    /// started); the three parts of a V3 file (spec §13.1).
    enum Part { Definition, Global, Local, Shapes };

    SceneBuilder(Diagnostics& diag, const ParseOptions& options);
    /// A copy of `from` that parses into `own` diagnostics and a description of its own, to be
    /// merged into `from` (merge): a file parsed ahead (piece null; `from` the tree's builder),
    /// or a piece of a mesh run of `from`'s open file, whose definitions it reads.
    SceneBuilder(const SceneBuilder& from, Diagnostics& own,
                 std::optional<Piece> piece = std::nullopt);

    // ---- errors and warnings: with the include chain as notes ----------------------------
    [[noreturn]] void fail(const SourceLoc& loc, const std::string& message) const;
    void warn(const SourceLoc& loc, std::string kind, std::string message) const;

    // ---- the tree and its files ------------------------------------------------------------
    /// The dialect the pre-scan settled and the top-level file's directory (V3 paths, spec
    /// §13.2).
    void set_dialect(Dialect d, std::string top_dir);
    /// A file's parse starts (its index in the scene taken, its include on the chain) or ends
    /// at `eof`: open groups, counts short of their declaration, texture indices out of range
    /// and V3 constructs left open are errors there; its description goes in its place.
    void open_file(const File& file);
    void close_file(const SourceLoc& eof);
    /// The #ray_file just read, if its file is for the driver to parse: the include's rules
    /// applied first (a cycle or too deep is an error; a file already parsed is numbered only).
    /// A copy for a file parsed ahead keeps its includes for the merge.
    std::optional<Include> take_include();
    /// A copy's result, in the tree's order. A piece of a run: its vertices or shapes after
    /// the open file's, its warnings, its counts. A file parsed ahead (`from` its #ray_file, its
    /// error if its parse failed): its warnings and key tracks up to its next #ray_file, which
    /// take_include() then gives; true while one is left, and the file is in place when false.
    bool merge(SceneBuilder& copy, const Include* from = nullptr,
               const std::exception_ptr& error = nullptr);
    /// The tree parsed: placements bounded, the missing-camera warning. The description.
    SceneDesc finish();
    /// A mesh run the pre-scan counted, parsed in pieces: room made once for the `n`
    /// directives after its first (vertices, else shapes of the innermost group or triangle
    /// list), the first `own` of it lent to this builder's walk, the rest to the pieces'
    /// copies, each of which writes its range in place; the merge closes up a range a piece
    /// wrote short (a degenerate triangle skipped). close_run: the array ends after what was
    /// written, the room given back (also when the pieces are dropped).
    void open_run(bool vertices, size_t n, size_t own);
    void close_run();

    // ---- counts (#*_num, spec §3.1) and the order of a file ---------------------------------
    /// `n` at n_loc declares the count; `room` bounds what it may reserve (the text left / 24).
    void declare_count(const SourceLoc& loc, CountKind k, int n, const SourceLoc& n_loc,
                       size_t room);
    void count_item(const SourceLoc& loc, CountKind k) const {
        Count& c = m_file->counts[k];
        ++c.found;
        if (c.declared && c.found > c.declared_n) fail(loc, too_many_message(k, c));
    }
    /// Whether directive `name` may come here; in a V3 shapes part, the rules of the open list
    /// (true: `name` opened the list its construct expected).
    bool place(const SourceLoc& loc, std::string_view name, Part part);

    // ---- definitions ---------------------------------------------------------------------
    /// #camera of either dialect: included files' cameras are syntax only; V0/V1 keep the
    /// first, V3 the last; the all-zero one is the default camera.
    void camera(const CameraDesc& c);
    void global_colour(bool background, const SourceLoc& loc, const Vec3& c);
    /// The warning of a light's attenuation (all zero: it never contributes).
    void attenuation(const LightDesc& l) const;
    /// A spot light's numbers, as both dialects read them (the cutoff and the drop-off at their
    /// places): checked, a V0 drop-off scaled, the warning of a cutoff beyond pi/2.
    void spot(LightDesc& l, const SourceLoc& cutoff_loc, const SourceLoc& dropoff_loc) const;
    /// A light as read: kept (top-level files) or ignored with a warning.
    void light(const LightDesc& l);
    void shader(std::string vertex, std::string fragment);
    void texture(const SourceLoc& loc, const SourceLoc& path_loc, const std::string& path);
    /// What a #material's numbers mean in the tree's dialect, each checked (the texture index
    /// aside); then the material with its texture index, whose range is checked at the end of
    /// the file.
    MaterialDesc material(const MaterialNumbers& m) const;
    void add_material(MaterialDesc m, const SourceLoc& texture_loc);
    void vertex(VertexDesc v);  // normal made unit
    /// #ray_file: the path found; its file numbered when the driver takes it (take_include).
    void ray_file(const SourceLoc& loc, const SourceLoc& path_loc, const std::string& path);
    void key_file(const SourceLoc& loc, const SourceLoc& path_loc, const std::string& path);

    // ---- the scene graph -----------------------------------------------------------------
    /// A material index of a shape (V0's -1 the default material), checked.
    int material_index(const SourceLoc& loc, int m) const;
    /// A vertex index of a triangle, checked against the file's vertices.
    void vertex_index(const SourceLoc& loc, int v) const;
    /// A shape as read into the innermost group, list or construct, unless it is degenerate
    /// or (`empty`, its T::kEmpty) an analytic shape of size 0: then skipped with a warning
    /// (spec §3.3). A V3 #shape_triangle takes its list's material.
    void shape(ShapeDesc&& s, const char* empty = nullptr);
    /// #ray_file_instance, its index checked.
    void instance(const SourceLoc& loc, const SourceLoc& index_loc, int i);
    /// A construct opened, within the nesting limits; V0/V1 #group_end and #joint_end, V3
    /// #shape_list_end close one.
    void open(const Construct& c);
    void close(const SourceLoc& loc, std::string_view directive);

private:
    /// merge() of a piece of a run: its vertices or shapes after the open file's, its warnings,
    /// its counts; its error, if any, thrown after its warnings.
    void merge_piece(SceneBuilder& piece, const std::exception_ptr& error);
    /// Where `path` is (spec §4.2, §13.2); when it is nowhere, an error naming `what`, or (with
    /// `tried`) nullopt and the places tried.
    std::optional<std::string> resolve(const SourceLoc& at, const std::string& path,
                                       const std::string& what, std::string* tried) const;

    /// The meaning state of an open file.
    struct OpenFile {
        FileDesc desc;
        size_t index = 0;  // in the scene's files
        bool top = false;
        bool included = false;  // its #ray_file is on the include chain
        bool graph_started = false;
        std::array<Count, kCountKinds> counts{};
        std::vector<KeyFile> key_files;
        std::vector<GroupDesc*> stack;  // open groups; stack[0] = &desc.root
        std::vector<char> stack_is_joint;
        bool warned_joint_identity = false;
        std::string dir;  // directory of this file, for relative paths
        struct TextureRef {
            SourceLoc loc;
            int index;
        };
        std::vector<TextureRef> texture_refs;  // material texture indices, checked at its end
        // V3 (spec §13.1): the part the file is in (0 global, 1 local, 2 shapes) and where the
        // local and shapes parts started; the open shape constructs; one warning per file for
        // lights and for #dynamic_affine without key files.
        int v3_part = 0;
        SourceLoc v3_local_start, v3_shapes_start;
        std::vector<V3Frame> v3;
        int v3_csg_depth = 0;
        bool warned_included_light = false, warned_dynamic_identity = false;
        // A piece of a mesh run: the file whose definitions (materials, vertices) its shapes
        // refer to; else this one.
        const FileDesc* defs = &desc;
        // A run in pieces (open_run): its room, the places [at, at + n) of the array; the range
        // this builder writes in place (first, next, end; next == end: none, or full).
        template <class T>
        struct Lent {
            T* first = nullptr;
            T* next = nullptr;
            T* end = nullptr;
        };
        struct Run {
            bool vertices = false;
            size_t at = 0, n = 0;
            VertexDesc* vertex_room = nullptr;
            ShapeDesc* shape_room = nullptr;
        } run;
        Lent<VertexDesc> lent_vertices;
        Lent<ShapeDesc> lent_shapes;
    };
    /// What the merge of a copy needs.
    struct Copy {
        bool piece = false;
        /// A file parsed ahead: its #ray_file directives, each with the number of warnings
        /// and key tracks made before it; how far the merge has come.
        struct Deferred {
            size_t warnings = 0, tracks = 0;
            Include include;
        };
        std::vector<Deferred> includes;
        size_t merged = 0, warnings = 0, tracks = 0;
        std::vector<int> track_of;  // its tracks' indices in the tree
        bool started = false;
    };

    Diagnostics& m_diag;
    ParseOptions m_options;
    SceneDesc m_scene;
    Dialect m_dialect = Dialect::V1;
    std::string m_top_dir = ".";                    // directory of the top-level file
    std::vector<SourceLoc> m_include_locs;          // #ray_file/#key_file, outermost first
    std::vector<std::unique_ptr<OpenFile>> m_open;  // the files being parsed, outermost first
    OpenFile* m_file = nullptr;                     // the innermost (stable: on the heap)
    std::shared_ptr<TextureCache> m_textures;
    std::optional<Include> m_include;  // the #ray_file just read
    std::optional<Copy> m_copy;        // this builder is a copy: what its merge needs
    bool m_seen_background = false, m_seen_ambient = false;
    SourceLoc m_camera_loc;          // V3: the last top-level #camera
    bool m_all_zero_camera = false;  // the top-level file's camera is the dummy
};

}  // namespace rt::parser_impl
