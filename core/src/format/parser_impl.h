// What the three parts of the .ray parser share; private to core/src/format. ParserBase holds the
// one error path, the token helpers and the state of the whole file tree. The directives
// (parser.cpp) derive from it; its dialect pre-scan is in dialect.cpp and its .key grammar in
// key_file.cpp. The shared helpers are defined in parser.cpp.
#pragma once

#include <array>
#include <atomic>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "format/lexer.h"
#include "rt/format/parser.h"
#include "rt/scene/scene_desc.h"
#include "rt/util/error.h"
#include "rt/util/file_io.h"

namespace rt::parser_impl {

/// A token or path in a message: quoted, control bytes and invalid UTF-8 as \xNN, cut after 200
/// bytes.
std::string quote(std::string_view s);
/// "end of file" or the quoted token.
std::string describe(const Token& t);
/// `lead` and the quoted path, then why read_file() refused it ("No such file or directory",
/// "'x' is a FIFO, not a regular file"): "cannot read key file 'x': ...".
std::string read_failure(const std::string& lead, const std::string& path, const std::string& why);
/// Filesystem queries that never throw (a path too long or otherwise invalid is "not there").
/// is_file: anything there but a directory; a FIFO or a device is found, and reading it is
/// refused with the reason (read_file), rather than "not found".
bool is_file(const std::filesystem::path& p);
std::string canonical_path(const std::string& path);
std::string lower(std::string_view s);
/// The shape kind whose directive is #shape_<kName> (spec §3.3, §13.5), if any (dialect.cpp).
std::optional<ShapeKind> shape_directive_kind(std::string_view directive);
/// V0/V1-only directives (spec §10 step 1): groups, joints, #background, #ambient, #*_num.
bool is_v01_directive(std::string_view directive);

// Limits of this reader (docs/format.md, "our choices"): they keep the recursion of every
// consumer of the group tree and the file tree shallow, and memory bounded by the input's size.
constexpr int kMaxGroupDepth = 10000;          // nested #group_begin/#joint_begin in one file
constexpr int kMaxIncludeDepth = 200;          // nested #ray_file includes
constexpr long long kMaxPlacements = 1 << 20;  // file copies placed in the world by instancing
constexpr int kMaxCsgDepth = 100;              // V3 CSG nodes nested in one file
constexpr int kMaxV3Depth = 1000;              // V3 lists, transforms and CSG nodes nested

// Items a #*_num count may declare.
enum CountKind { kLights, kTextures, kMaterials, kVertices, kRayFiles, kKeyFiles, kCountKinds };
inline constexpr std::array<const char*, kCountKinds> kCountDirective = {
    "#light_num", "#texture_num", "#material_num", "#vertex_num", "#ray_file_num", "#key_file_num"};
inline constexpr std::array<const char*, kCountKinds> kItemDirective = {
    "light", "#texture", "#material", "#vertex", "#ray_file", "#key_file"};

struct Count {
    bool declared = false;
    int declared_n = 0;
    SourceLoc loc;
    int found = 0;
};

// A parsed .key file (spec §14.1): every key of every DOF, bottom rows set to (0, 0, 0, 1).
struct KeyFile {
    std::string path;
    std::string named;  // the path as written in the .ray file
    double duration = 1;
    std::vector<std::string> names;       // the DOF names as written
    std::vector<SourceLoc> name_locs;     // where each name is
    std::vector<std::vector<Mat4>> keys;  // [dof][frame]
    std::vector<int> track;               // [dof]: index into SceneDesc::tracks, or -1
    // The DOFs by name, so binding a joint is one look-up, not a scan of every name: exactly as
    // written, and with ASCII case ignored (lower case; every DOF of that name, in file order).
    std::unordered_map<std::string, size_t> by_name;
    std::unordered_map<std::string, std::vector<size_t>> by_lower_name;
};

// One open construct of a V3 shapes part (spec §13.5). The parser keeps them on an explicit
// stack, so deep nesting never recurses; a finished construct is delivered to the one below.
struct V3Frame {
    enum Kind { Root, List, Affine, TrianglesHead, Triangles, CsgHead, CsgList, Difference };
    Kind kind = Root;
    SourceLoc loc;
    std::string name;        // the directive that opened it
    GroupDesc group;         // Root, List, Triangles, Affine
    CsgDesc csg;             // CsgHead, CsgList, Difference
    int material = 0;        // Triangles
    bool has_child = false;  // Affine
};

// A finished V3 shape handed to its parent frame.
struct V3Node {
    enum Kind { Empty, Shape, Instance, Group, List, Csg };
    Kind kind = Empty;
    SourceLoc loc;
    ShapeDesc shape;
    InstanceDesc instance;
    GroupDesc group;  // Group and List (List: a #shape_list_begin list, which folds)
    CsgDesc csg;
};

// A run of one mesh directive (#vertex or #shape_triangle, one after another) in a file, as the
// pre-scan found it, with a mark every ParseOptions::piece directives where the parse may cut it
// between threads (mesh_runs.cpp). Only runs of at least two pieces are kept.
struct MeshRun {
    struct Mark {
        size_t offset = 0;  // of the directive, in bytes
        int line = 0, col = 0;
        size_t index = 0;  // in the run
    };
    bool vertices = false;    // #vertex, else #shape_triangle
    std::vector<Mark> marks;  // marks[0] is the run's first directive
    size_t count = 0;         // directives in the run
    size_t end = 0;           // offset of the directive after the run (SIZE_MAX: the end)
};

// What a piece of a run parsed on another thread reports besides its shapes and vertices: its
// warnings and skipped shapes, handed on in file order once the pieces before it are merged.
struct PieceOutput {
    struct Pending {
        SourceLoc loc;
        std::string kind, message;
        std::vector<SourceLoc> chain;
    };
    std::vector<Pending> warnings;
    size_t skipped = 0;
};

// Per-file parse state.
struct FileState {
    Lexer lex;
    FileDesc desc;
    bool top = false;
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
    std::vector<TextureRef> texture_refs;  // material texture indices, checked at end of file
    // V3 (spec §13.1): the part the file is in (0 global, 1 local, 2 shapes) and where the local
    // and shapes parts started; the open shape constructs; one warning per file for lights.
    int v3_part = 0;
    SourceLoc v3_local_start, v3_shapes_start;
    std::vector<V3Frame> v3;
    int v3_csg_depth = 0;
    bool warned_included_light = false, warned_dynamic_identity = false;

    // A piece of a run parsed on another thread: the file's state it started from, whose
    // definitions (materials, vertices) its shapes refer to.
    const FileState* parent = nullptr;
    const FileDesc& defs() const { return parent ? parent->desc : desc; }
    size_t counted = 0;  // bytes of the text up to here added to ParseProgress::done
    // While a run is parsed in pieces, each piece (the file's own walk the first) writes the
    // run's vertices or shapes into its own range of the file's array, made room for before the
    // pieces start: where the next one goes and the range's end.
    template <class T>
    struct Slots {
        T* next = nullptr;
        T* end = nullptr;
    };
    Slots<VertexDesc> vertex_slots;
    Slots<ShapeDesc> shape_slots;

    FileState(std::string_view text, const std::string* name) : lex(text, name) {}
};

class ParserBase {
protected:
    ParserBase(Diagnostics& diag, const ParseOptions& options) : m_diag(diag), m_options(options) {}
    virtual ~ParserBase() = default;

    // ---- errors: every parse error goes through here, with the include chain as notes ----
    [[noreturn]] void fail(const SourceLoc& loc, const std::string& message) const {
        std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
        throw SceneError(loc, message, std::move(chain));
    }
    [[noreturn]] void fail(const FileState& fs_, const Token& t, const std::string& message) const {
        fail(fs_.lex.loc(t), message);
    }
    // Warnings carry the include chain too (spec §2). On a thread parsing a piece of a run they
    // wait in its PieceOutput, so they reach m_diag in file order.
    void warn(const SourceLoc& loc, std::string kind, std::string message) const {
        std::vector<SourceLoc> chain(m_include_locs.rbegin(), m_include_locs.rend());
        if (t_piece)
            t_piece->warnings.push_back(
                {loc, std::move(kind), std::move(message), std::move(chain)});
        else
            m_diag.warn(loc, std::move(kind), std::move(message), std::move(chain));
    }
    // A vertex, or a shape of group list `to`, into the description, or into the slots of a
    // piece of a run (mesh_runs.cpp).
    void add_vertex(FileState& f, const Token& d, const VertexDesc& v) const {
        if (!f.vertex_slots.next) return f.desc.vertices.push_back(v);
        if (f.vertex_slots.next == f.vertex_slots.end) fail(f, d, kRunOverflow);
        *f.vertex_slots.next++ = v;
    }
    void add_shape(FileState& f, const Token& d, HugePageVector<ShapeDesc>& to,
                   ShapeDesc&& s) const {
        if (!f.shape_slots.next) return to.push_back(std::move(s));
        if (f.shape_slots.next == f.shape_slots.end) fail(f, d, kRunOverflow);
        *f.shape_slots.next++ = std::move(s);
    }
    static constexpr const char* kRunOverflow =
        "internal error: a mesh run longer than the pre-scan found";
    /// A degenerate shape left out, with its warning ("degenerate triangle skipped").
    void skip_shape(const SourceLoc& loc, const char* kind) {
        if (t_piece)
            ++t_piece->skipped;
        else
            ++m_scene.skipped_shapes;
        warn(loc, std::string("skip:") + kind, std::string(kind) + " skipped");
    }
    static inline thread_local PieceOutput* t_piece = nullptr;

    // ---- the walk over a file's directives (mesh_runs.cpp) -----------------------------------
    /// One directive, by the file's dialect.
    virtual void dispatch(FileState& f, const Token& d) = 0;
    /// Parses from token `t` to the first directive at or after byte `bound` (or the end of the
    /// file, or until *stop is set), which it returns unparsed.
    Token walk(FileState& f, Token t, size_t bound, const std::atomic<bool>* stop = nullptr);
    /// The directives of a file, the long runs of mesh directives in pieces on several threads.
    void walk_file(FileState& f);
    /// The threads a run is cut for (ParseOptions::threads; 1 where none can start).
    unsigned parse_threads() const;
    /// ParseProgress: the bytes of f's text up to `offset` are parsed (counted once each).
    void count_progress(FileState& f, size_t offset) const;
    /// ParseProgress::cancel set: throws "loading cancelled" at `loc`.
    void check_cancel(const SourceLoc& loc) const;
    /// ParseProgress::total grows by a text read.
    void count_text(size_t bytes) const;

    // ---- token helpers (parser.cpp) ------------------------------------------------------
    SourceLoc arg_loc(FileState& f, const Token& dir, const Token& bad) const;
    double real(FileState& f, const Token& dir, int count);
    Vec3 vec3(FileState& f, const Token& dir, int count);
    int integer(FileState& f, const Token& dir, std::string_view what, SourceLoc* loc = nullptr);
    std::string word(FileState& f, const Token& dir, std::string_view what, bool ascii = false);
    Vec3 colour(FileState& f, const Token& dir, int count, std::string_view what);
    static std::string fmt(double v);
    static std::string fmt(const Vec3& v);

    // ---- counts, paths, matrices (parser.cpp) --------------------------------------------
    void declare_count(FileState& f, const Token& dir, CountKind k);
    void count_item(FileState& f, const Token& dir, CountKind k);
    std::string resolve(FileState& f, const Token& at, const std::string& path,
                        const std::string& what);
    /// resolve() without the error: nullopt, with the places tried in *tried.
    std::optional<std::string> try_resolve(FileState& f, const Token& at, const std::string& path,
                                           std::string* tried);
    CameraDesc read_camera(FileState& f, const Token& d);  // the ten numbers of #camera
    /// The course's dummy camera (all ten numbers 0, spec §13.3) in a top-level file: the default
    /// camera with a warning. Returns whether c is that camera.
    bool dummy_camera(const CameraDesc& c);
    void validate_camera(FileState& f, const Token& d, const CameraDesc& c);
    TriangleDesc triangle_indices(FileState& f, const Token& d);
    static bool degenerate_triangle(const FileDesc& file, const TriangleDesc& t);
    void check_matrix(const Mat4& m, const SourceLoc& loc, const std::string& what);

    // ---- dialect detection (dialect.cpp) -------------------------------------------------
    void detect_dialect(std::string_view text, const std::string& name,
                        const std::string& canonical, const std::string& dir);
    /// The file's text (read once); nullptr, with the reason in *why, when it cannot be read.
    const FileBytes* cached_text(const std::string& path, const std::string& canonical,
                                 std::string* why = nullptr);

    // ---- key files (key_file.cpp) --------------------------------------------------------
    KeyFile parse_key_file(const std::string& text, const std::string& path);
    /// The track (index into m_scene.tracks) of DOF `name` of f's key files (spec §14.2).
    int bind_dof(FileState& f, const Token& nt, const std::string& name);

    Diagnostics& m_diag;
    bool v3_all_zero_camera = false;  // the top-level file's camera is the dummy (dummy_camera)
    ParseOptions m_options;
    std::vector<SourceLoc> m_include_locs;     // #ray_file directives, outermost first
    std::map<std::string, FileBytes> m_texts;  // included files read, not yet parsed
    Dialect m_dialect = Dialect::V1;
    SceneDesc m_scene;
    std::string m_top_dir = ".";  // directory of the top-level file (V3 paths, spec §13.2)
    // First marker of each kind (spec §10 step 1), for messages: "V3 '#static_affine' at F:L:C".
    std::string m_v3_marker;
    // What the pre-scan counted in each file (by canonical path), for the parse's reservations.
    struct FileSizes {
        size_t vertices = 0;
        size_t top_shapes = 0;  // #shape_* directives outside any group (V0/V1)
        std::vector<MeshRun> runs;
    };
    std::map<std::string, FileSizes> m_sizes;

private:
    Token parse_run(FileState& f, const Token& first, const MeshRun& run);
    template <class IsVertices>
    Token parse_pieces(FileState& f, const MeshRun& run, IsVertices kind);
    struct Scan;
    std::optional<std::string> find_file(const std::string& dir, const std::string& path,
                                         bool v3) const;
    void prescan(std::string_view text, const std::string& name, const std::string& canonical,
                 const std::string& dir, Scan& scan);
    void prescan_directive(Lexer& lex, const Token& t, const std::string& dir, Scan& scan);
    void prescan_marker(const SourceLoc& loc, std::string_view what, bool v3, Scan& scan);
    bool wants_marker(bool v3, const Scan& scan) const;
    void run_prescan(std::string_view text, const std::string& name, const std::string& canonical,
                     const std::string& dir, bool v3, Scan& scan);

    SourceLoc m_first_v0, m_first_v1;  // first material of each dialect (pre-scan)
    bool m_default_use = false;        // some shape uses material index -1
};

/// The V3 directives (parser_v3.cpp). The definitions V3 shares with V1 (#texture, #material,
/// #vertex, #ray_file, #key_file and the four classic primitives) are the V1 parser's, reached
/// through these hooks.
class ParserV3 : public ParserBase {
protected:
    using ParserBase::ParserBase;

    virtual void texture(FileState& f, const Token& d) = 0;
    virtual void material(FileState& f, const Token& d) = 0;
    virtual void vertex(FileState& f, const Token& d) = 0;
    virtual void ray_file(FileState& f, const Token& d) = 0;
    virtual void key_file(FileState& f, const Token& d) = 0;
    virtual int material_index(FileState& f, const Token& d) = 0;
    /// Sphere, box, cylinder or cone after its material index; false when it is skipped.
    virtual bool primitive(FileState& f, const Token& d, ShapeDesc& s) = 0;

    void v3_directive(FileState& f, const Token& d);
    void v3_end_of_file(FileState& f, const SourceLoc& eof);
    SourceLoc m_camera_loc;  // the last top-level #camera

private:
    void v3_order(FileState& f, const Token& d, int part);
    void v3_camera(FileState& f, const Token& d);
    void v3_light(FileState& f, const Token& d);
    void v3_shader(FileState& f, const Token& d);
    void v3_shape(FileState& f, const Token& d);
    bool v3_list_directive(FileState& f, const Token& d);
    void v3_push(FileState& f, const Token& d, V3Frame::Kind kind);
    void v3_deliver(FileState& f, V3Node node);
    void v3_receive(FileState& f, V3Frame& to, V3Node& node);
    V3Node v3_finish(FileState& f, V3Frame& fr);
    void v3_affine(FileState& f, const Token& d);
    void v3_dynamic(FileState& f, const Token& d);
    void v3_triangle(FileState& f, const Token& d);
    void v3_instance(FileState& f, const Token& d);
};

}  // namespace rt::parser_impl
