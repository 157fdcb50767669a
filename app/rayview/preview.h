// The rasterized preview of a RenderScene (OpenGL 3.3 core, no window code), drawn with the
// tracer's local lighting model (shaders/preview.{vert,frag}) and the tracer's exact camera, so
// the preview and the trace of a view agree. Needs a current GL context: the viewer's (GLFW) or
// the tests' (OSMesa).
#pragma once

#include <string>
#include <vector>

#include "rt/camera.h"
#include "rt/render_scene.h"

namespace rt::view {

/// Column-major 4x4 matrices as GL wants them.
struct GlMatrices {
    float clip_from_world[16];
};

/// The projection that maps the tracer's pixel rays (spec §6) onto GL's pixel centres.
GlMatrices camera_matrices(const Camera& camera, const Bounds3& world);

/// One end of an overlay line segment.
struct LineVertex {
    float position[3];
    float color[3];
};

/// Overlay geometry: a marker per light (a cross for point lights, a cone for spots, an arrow for
/// directional ones) and, up to `bvh_depth` levels, the boxes of the instances and of their
/// BVH nodes (the flattened groups' boxes), in world space.
std::vector<LineVertex> overlay_lines(const RenderScene& scene, bool lights, int bvh_depth);

class Preview {
public:
    /// Compiles the preview program from `shader_dir`; throws std::runtime_error with the shader
    /// file's name and the compiler's log.
    explicit Preview(const std::string& shader_dir);
    ~Preview();
    Preview(const Preview&) = delete;
    Preview& operator=(const Preview&) = delete;

    /// Uploads the scene's meshes (tessellated with `detail` segments) and textures.
    void load(const RenderScene& scene, int detail = 48);
    /// Clears to the scene's background and draws every instance.
    void draw(const RenderScene& scene, const Camera& camera, int width, int height) const;
    /// Draws line segments (pairs of vertices) over what draw() left, depth-tested.
    void draw_lines(const std::vector<LineVertex>& lines, const RenderScene& scene,
                    const Camera& camera) const;

private:
    struct Range {
        int material;
        unsigned first, count;  // in indices
    };
    struct SetBuffers {
        unsigned vao = 0, vbo = 0, ebo = 0;
        std::vector<Range> ranges;
    };
    void release();

    unsigned m_program = 0, m_line_program = 0;
    unsigned m_line_vao = 0, m_line_vbo = 0;
    std::vector<SetBuffers> m_sets;
    std::vector<unsigned> m_textures;
};

}  // namespace rt::view
