// The plain scene description: what the .ray files say, after the dialect is resolved, with every
// node remembering its file, line and column. The parser fills it; compile_scene() turns it into
// the render representation. Nothing here renders.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rt/image/image.h"
#include "rt/scene/animation.h"
#include "rt/scene/scene_parts.h"
#include "rt/shapes/shapes.h"
#include "rt/util/error.h"
#include "rt/util/huge_pages.h"
#include "rt/util/light_kind.h"
#include "rt/util/math.h"

namespace rt {

enum class Dialect { V0, V1, V3 };

/// V0 writes the specular exponent and the spot drop-off as fractions of 128 (spec §3.2, §7.2):
/// e = 128 * kspec, p = 128 * dor.
inline constexpr double kV0ExponentScale = 128.0;
const char* dialect_name(Dialect d);

/// The camera as the file wrote it (spec §6.1): its pose, and where.
struct CameraDesc : CameraPose {
    SourceLoc loc;
};

/// A light as the file wrote it: the light (rt/scene/scene_parts.h), and where. Its direction is
/// as written; the compile makes it unit.
struct LightDesc : Light {
    SourceLoc loc;
};

/// A material as the file wrote it: its terms, where, and its name. Its texture is an index into
/// the file's textures (the compile renumbers it into the scene's).
struct MaterialDesc : Material {
    SourceLoc loc;
    std::string name;  // the !...! string, stored, never interpreted
};

/// The V0 built-in material that shape material index -1 refers to (spec §3.2).
MaterialDesc v0_default_material();

struct TextureDesc {
    SourceLoc loc;
    std::string path;  // as resolved
    std::shared_ptr<const TextureImage> image;
};

struct VertexDesc {
    Vec3 position{0.0};
    Vec3 normal{0.0};  // normalised when read; zero = no normal
    Vec2 uv{0.0};
};

/// The description of a shape is the shape itself (shapes.h) except for two kinds: a box is
/// written with full side lengths, a triangle with vertex indices of its file.
struct BoxDesc {
    Vec3 centre{0.0};
    Vec3 size{1.0};  // full side lengths
    bool operator==(const BoxDesc&) const = default;
    template <class P>
    void params(P& p) {  // as #shape_box lists them (shapes.h)
        p.point(centre);
        for (int i = 0; i < 3; ++i) p.size(size[i], "box size");
    }
};
inline Box to_shape(const BoxDesc& b) { return {b.centre, 0.5 * b.size}; }
template <class T>
const T& to_shape(const T& shape) {
    return shape;
}
struct TriangleDesc {
    int v[3] = {0, 0, 0};  // vertex indices of this file
    bool operator==(const TriangleDesc&) const = default;
};

/// The description type of each shape kind.
template <class T>
struct DescOf {
    using type = T;
};
template <>
struct DescOf<Box> {
    using type = BoxDesc;
};
template <>
struct DescOf<Triangle> {
    using type = TriangleDesc;
};
template <class V>
struct ShapeDescVariant;
template <class... T>
struct ShapeDescVariant<std::variant<T...>> {
    using type = std::variant<typename DescOf<T>::type...>;
};

struct ShapeDesc {
    SourceLoc loc;
    int material = 0;  // index into the file's materials; -1 = V0 default
    /// The alternatives in ShapeKind's order: geometry.index() is the kind.
    ShapeDescVariant<Shape>::type geometry;
};

struct InstanceDesc {
    SourceLoc loc;
    int ray_file = 0;  // index into the file's ray_files
};

enum class CsgOp { Union, Intersection, Difference };
const char* csg_op_name(CsgOp op);  // "union", "intersection", "difference"

struct CsgDesc;

/// A list of shapes in the frame p_parent = matrix * p_local: a V0/V1 #group_begin (or
/// #joint_begin), a V3 #static_affine (or #dynamic_affine) and its one child, a V3
/// #shape_list_begin (identity), a #shape_triangles list (its triangles, each with the list's
/// material), an operand of a CSG node. Children of one kind keep their order; the kinds are
/// not interleaved (a list is a union of surfaces, so their order does not matter).
///
/// The V3 parser folds: a #static_affine, #dynamic_affine or CSG operand whose one child is a
/// #shape_list_begin list is that list with the matrix (or joint) set, so parse -> write ->
/// parse gives the same description.
struct GroupDesc {
    SourceLoc loc;
    Mat4 matrix{1.0};
    std::string joint;  // non-empty for #joint_begin and #dynamic_affine (the DOF name)
    /// A joint bound to a DOF: its index into SceneDesc::tracks (-1: a plain group, or a joint
    /// without key files, which is the identity). `matrix` is then the track's key 0 as read.
    int track = -1;
    HugePageVector<ShapeDesc> shapes;  // a mesh's (80 bytes each) faulted in 2 MB at a time
    std::vector<GroupDesc> groups;
    std::vector<InstanceDesc> instances;
    std::vector<CsgDesc> csgs;  // V3 only
};

/// A V3 CSG node (spec §13.8). Every operand is one child of the node, wrapped in a list (so a
/// union of a sphere and a #shape_list_begin list of two boxes has two operands); a difference
/// has exactly two (A - B). An empty operand (a degenerate shape skipped with a warning) is an
/// empty shape: no surface, nothing inside.
struct CsgDesc {
    SourceLoc loc;
    CsgOp op = CsgOp::Union;
    std::vector<GroupDesc> operands;
};

/// One parsed .ray file. Its index spaces (materials, textures, vertices, ray files) are its own.
struct FileDesc {
    std::string path;            // as resolved (for messages)
    std::string canonical_path;  // identity: parsed once per canonical path
    std::vector<TextureDesc> textures;
    std::vector<MaterialDesc> materials;
    HugePageVector<VertexDesc> vertices;
    std::vector<int> ray_files;          // #ray_file index -> index into SceneDesc::files
    std::vector<std::string> key_files;  // as resolved (the DOFs joints use are SceneDesc::tracks)
    GroupDesc root;                      // implicit identity group (V3: the root list)
};

/// Tight bounds of a shape of `file` under p' = m p (exact for the analytic kinds, the hull of
/// the vertices for a triangle; vertex indices out of range are ignored).
Bounds3 bounds(const ShapeDesc& shape, const FileDesc& file, const Mat4& m);

struct SceneDesc {
    Dialect dialect = Dialect::V1;
    std::optional<CameraDesc> camera;  // absent: default camera (spec §6.3)
    Vec3 background{0.0};
    Vec3 ambient{0.0};
    std::vector<LightDesc> lights;  // top-level file only
    std::vector<FileDesc> files;    // files[0] is the top-level file
    /// The DOFs that joints are bound to (spec §14.2), each once however many joints share it.
    std::vector<KeyTrack> tracks;
    size_t skipped_shapes = 0;  // degenerate shapes skipped with a warning
    /// V3 #shader of the top-level file (the last one wins): recorded, never opened (spec §13.3).
    std::string shader_vertex, shader_fragment;
    /// Textures that could not be opened or decoded and stand in as a checker
    /// (ParseOptions::missing_textures), as named in their file.
    std::vector<std::string> missing_textures;
};

/// Where the directive at `loc` sits: its file and the groups (and CSG nodes) above it,
/// outermost first, as "pawn.ray > group at line 12 > joint 'arm' at line 15"; "" when no file of
/// `desc` holds it. What the viewer's picking and the ray tree (rt/render/inspect.h) name.
std::string group_path(const SceneDesc& desc, const SourceLoc& loc);

}  // namespace rt
