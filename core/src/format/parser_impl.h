// What the parts of the .ray parser share, private to core/src/format: the records of a file's
// meaning (counts, key files, V3 constructs), the pre-scan's mesh runs, the texture cache and the
// helpers for messages and paths (defined in parser.cpp). The driver (driver.h) walks the file
// tree, handing each directive to the grammar walk of its dialect (grammar.h), which reads it
// into the SceneBuilder (scene_builder.h).
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

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
/// For messages: a number as C++ streams write it.
std::string fmt(double v);
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

/// "more #material than declared by #material_num at F:L:C" (scene_builder.cpp).
std::string too_many_message(CountKind k, const Count& c);

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

/// Textures decoded once per scene (shared by the builders of files parsed ahead, on other
/// threads): every naming of a file shares the image, or the error.
struct TextureCache {
    struct Decoded {
        std::shared_ptr<const TextureImage> image;  // null when it does not decode
        std::string error;
    };
    /// The texture at `path` (found), decoded the first time within what the scene's texel
    /// budget has left (parser.cpp).
    Decoded decode(const std::string& path);

private:
    std::mutex m_mutex;
    std::map<std::string, Decoded> m_decoded;  // by canonical path
    uint64_t m_texels = 0;                     // of every texture decoded (max_scene_texels())
};

}  // namespace rt::parser_impl
