// What the parts of the .ray parser share, private to core/src/format: the per-file state, the
// limits of the reader and the helpers for messages and paths (defined in parser.cpp). The
// driver (driver.h) walks the file tree, handing each directive to the grammar walk of its
// dialect (grammar.h), which reads it into the SceneBuilder (scene_builder.h).
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
#include "rt/util/limits.h"
#include "rt/util/text.h"

namespace rt::parser_impl {

/// What a file whose first token is not printable text is told, instead of that token (a
/// binary file, or a secret that is not a scene: its bytes never reach the message):
/// "'x' is not a .ray scene: its first bytes are not printable text".
std::string not_text_message(const std::string& name, const std::string& what = "a .ray scene");
/// "end of file" or the quoted token.
std::string describe(const Token& t);
/// `lead` and the quoted path, then why read_file() refused it ("No such file or directory",
/// "'x' is a FIFO, not a regular file"): "cannot read key file 'x': ...".
std::string read_failure(const std::string& lead, const std::string& path, const std::string& why);
/// Filesystem queries that never throw (a path too long or otherwise invalid is "not there").
/// is_file: anything there but a directory; a FIFO or a device is found, and reading it is
/// refused with the reason (read_file), rather than "not found".
bool is_file(const std::filesystem::path& p);
bool is_dir(const std::filesystem::path& p);
std::string canonical_path(const std::string& path);
std::string lower(std::string_view s);
/// The shape kind whose directive is #shape_<kName> (spec §3.3, §13.5), if any (dialect.cpp).
std::optional<ShapeKind> shape_directive_kind(std::string_view directive);
/// V0/V1-only directives (spec §10 step 1): groups, joints, #background, #ambient, #*_num.
bool is_v01_directive(std::string_view directive);

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

}  // namespace rt::parser_impl
