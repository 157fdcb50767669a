// The rasterized preview of a RenderScene (OpenGL 3.3 core, no window code), drawn with the
// tracer's local lighting model (shaders/preview.{vert,frag}) and the tracer's exact camera, so
// the preview and the trace of a view agree. Needs a current GL context: the viewer's (GLFW) or
// the tests' (OSMesa).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/gl_util.h"
#include "rt/image/image.h"
#include "rt/render/camera.h"
#include "rt/render/plan.h"
#include "rt/render_scene.h"
#include "state/csg_preview.h"
#include "state/overlay.h"
#include "state/preview_geometry.h"
#include "state/preview_ranges.h"

namespace rt::view {

/// Column-major 4x4 matrices as GL wants them.
struct GlMatrices {
    float clip_from_world[16];
};

/// The projection that maps the tracer's pixel rays (spec §6) onto GL's pixel centres; its near
/// and far planes enclose `world` (see view_bounds).
GlMatrices camera_matrices(const Camera& camera, const Bounds3& world);

/// How linear colours are shown: 2^exposure_stops times, then the tonemap (as the trace's
/// display_transform()).
struct DisplaySettings {
    double exposure_stops = 0;
    Tonemap tonemap = Tonemap::Clamp;
};

class Preview {
public:
    /// Compiles the preview program from `shader_dir`; throws std::runtime_error with the shader
    /// file's name and the compiler's log.
    explicit Preview(const std::string& shader_dir);

    /// Uploads the scene's meshes (tessellated with `detail` segments) and textures.
    void load(const RenderScene& scene, int detail = 48);
    /// The same from geometry prepared for this scene (prepare_preview()).
    void load(const RenderScene& scene, const PreviewGeometry& geometry);
    /// Clears to the scene's background and draws every instance, lit by the plan's lights with
    /// a program compiled for what the plan says the scene uses. With the plan's shadows, the
    /// first kMaxShadowLights lights cast shadows from opaque materials through shadow maps,
    /// rendered again only when the lights or the scene change. With `max_depth` >= 2 (the
    /// trace's recursion depth), reflecting and transmitting materials add K_S times the
    /// reflected and T times the refracted view from environment cube maps (one per object, up
    /// to kMaxEnvMaps, the largest first; the rest share the nearest), rendered again only when
    /// the lights, the shadows or the scene change; 1 draws local shading only. `display`: the
    /// trace pane's exposure and tonemap (rt::display_transform), applied to every pixel, the
    /// background included, so the two panes show the same transform.
    void draw(const RenderScene& scene, const RenderPlan& plan, const Camera& camera, int width,
              int height, int max_depth = 1, const DisplaySettings& display = {});
    /// The scene's materials were edited: the environment maps are chosen again (which objects
    /// reflect) and the shadow and transmittance maps rendered again (which cast them).
    void materials_changed(const RenderScene& scene);
    /// A material now uses a texture that was not uploaded, on a set uploaded without texture
    /// coordinates: load() again (with prepare_preview(scene, detail())).
    bool needs_upload(const RenderScene& scene) const;
    int detail() const { return m_detail; }
    /// Draws line segments (pairs of vertices) over what draw() left, depth-tested, or over
    /// everything with `on_top` (a ray tree, whose rays run inside solids too).
    void draw_lines(const std::vector<LineVertex>& lines, const RenderScene& scene,
                    const Camera& camera, bool on_top = false) const;

    static constexpr int kMaxShadowLights = 4;
    static constexpr int kShadowResolution = 1024;
    static constexpr int kTransmitResolution = 512;
    static constexpr int kMaxEnvMaps = 8;
    static constexpr int kMaxPlanes = 4;  // planar reflections drawn a frame
    static constexpr int kEnvResolution = 128;
    static constexpr int kCsgRow = 1024;  // CSG texels per row of their texture (csg.frag's)

    /// The environment maps the last draw used (0 without reflections).
    int environment_maps() const { return m_env_drawn; }
    /// The view is moving (the viewer's drag or orbit): one planar reflection a frame rather
    /// than kMaxPlanes, each a pass over the whole scene, and big meshes drawn coarse
    /// (PreviewGeometry::Set::coarse; software GL: the orbit's frame time).
    bool moving = false;
    /// The planar reflections the last draw rendered (0 without reflections).
    int planar_reflections() const { return static_cast<int>(m_planes.size()); }
    /// Environment maps left to render again (after a change of the lights or the shadows): a
    /// draw renders faces of maps for about `env_budget_ms` (at least one), and shows stale ones,
    /// or none before every map has its first bounce, until then. Draw again while this is true.
    bool environment_pending() const { return m_env_next < 12 * m_env.size(); }
    double env_budget_ms = kInf;  // the viewer's frames: a few ms; the tests: all at once

    /// The defines the last draw compiled its program with (RT_POINT, RT_SHADOWS, ...): only
    /// the light kinds and features the scene has.
    const std::vector<std::string>& active_defines() const { return m_defines; }
    /// Floats of vertex data the last load() uploaded (uv only for textured sets).
    size_t uploaded_floats() const { return m_uploaded_floats; }
    /// Triangles the last draw() drew in its main pass (the coarse sets' while moving).
    size_t triangles_drawn() const { return m_triangles_drawn; }

private:
    struct SetBuffers {
        GlVertexArray vao;  // none for a set no instance places
        GlBuffer vbo, ebo;
        bool uvs = false;                  // texture coordinates uploaded
        std::vector<PreviewRange> ranges;  // state/preview_ranges.h
        GlTexture csg_texture;             // the CSG trees (csg_preview.h), none without CSG
        int csg_nodes = 0, csg_children = 0, csg_leaves = 0;
        /// The set's coarse version (PreviewGeometry::Set::coarse), drawn while the view
        /// moves; its full_range gives, per range, the full set's range of its material.
        std::unique_ptr<SetBuffers> coarse;
        std::vector<size_t> full_range;
    };
    static SetBuffers upload_set(const PreviewMesh& mesh, const std::vector<PreviewShape>& shapes,
                                 bool textured, const CsgTexels& csg, size_t* floats);
    // What a shadow map was rendered for, to know when to render it again.
    struct ShadowView {
        int layer = -1;  // first layer in the array, -1: none
        Vec3 centre{0.0}, a1{0.0}, a2{0.0};
        double scale = 1.0;  // half extent (directional) or far distance (point, spot)
        LightKind kind = LightKind::Point;
        Vec3 position{0.0}, direction{0.0};
        bool operator==(const ShadowView&) const = default;
    };
    unsigned program_for(const std::vector<std::string>& defines);
    /// Which lights get a shadow map (the first kMaxShadowLights that light), and the view each
    /// is rendered with; `*layers`: the array layers they take.
    static std::vector<ShadowView> shadow_views(const RenderScene& scene,
                                                const std::vector<Light>& lights, int* layers);
    void render_shadow_maps(const RenderScene& scene, const std::vector<Light>& lights);
    /// The transmittance maps of the same views (m_transmit_tex), when a material transmits.
    void render_transmit_maps(const RenderScene& scene, const std::vector<ShadowView>& views,
                              int layers);
    /// The clip matrix shadow view `v`'s face is rendered with (row-major).
    struct ClipMatrix {
        double m[4][4] = {};
    };
    static ClipMatrix shadow_clip_from_world(const ShadowView& v, int face, const Bounds3& w);
    /// What draw_instances() draws: only opaque triangles, unshaded (shadow maps); with the
    /// environment maps bound per object; all but the objects that share map `skip_map` (that
    /// map's own pass).
    struct DrawPass {
        bool opaque_only = false, reflections = false;
        bool mirrored = false;  // a planar reflection's pass: every winding seen is reversed
        bool transparent_only = false;  // only transmitting materials, their T in u_transmit
        bool coarse = false;  // the sets' coarse versions where they have one (the view moves)
        bool main = false;    // the pane's own pass (counted in triangles_drawn)
        int skip_map = -1;
    };
    void draw_instances(const RenderScene& scene, unsigned program, const DrawPass& pass) const;
    /// The defines of the program for what the plan uses (preview.frag's header).
    std::vector<std::string> frame_defines(const RenderPlan& plan, bool shadows) const;
    /// The camera, the lights and the shadow maps into `program`'s uniforms.
    void set_frame_uniforms(unsigned program, const RenderScene& scene, const RenderPlan& plan,
                            const Camera& camera, bool shadows) const;
    // Environment maps (environment.cpp): which objects reflect or transmit, and their maps.
    struct EnvMap {
        GlTexture cube;    // RGBA32F: colour, distance from centre
        Vec3 centre{0.0};  // of the largest object that uses it
    };
    void choose_environment_maps(const RenderScene& scene);
    void update_environment_maps(const RenderScene& scene, const RenderPlan& plan, bool shadows);
    void render_environment_face(const RenderScene& scene, const RenderPlan& plan, bool shadows,
                                 size_t map, int face, int bounce);

    // Planar reflections (planar.cpp): the largest flat faces of reflecting materials, facing
    // the eye, get the scene drawn mirrored about their plane into a layer of m_planar_tex, which
    // preview.frag reads at the fragment's pixel for fragments on that plane (the cube maps
    // cannot show a plane's reflection: their centre is not on it).
    struct PlanarView {
        glm::dvec4 plane{0.0};  // world n.p + d, positive on the eye's side
        double epsilon = 0;     // how far from it a fragment still counts as on it
    };
    std::vector<PlanarView> choose_planes(const RenderScene& scene, const Camera& camera) const;
    void render_planar_maps(const RenderScene& scene, const RenderPlan& plan, const Camera& camera,
                            bool shadows, int width, int height);
    void set_planar_uniforms(unsigned program, int width, int height) const;
    std::vector<PlanarView> m_planes;  // those the last draw rendered
    GlFramebuffer m_planar_fbo;
    GlTexture m_planar_tex;  // RGBA16F array, one layer a plane, half the pane's resolution
    GlRenderbuffer m_planar_depth;
    int m_planar_w = 0, m_planar_h = 0;

    std::string m_shader_dir;
    std::map<std::vector<std::string>, GlProgram> m_programs;  // by defines
    std::vector<std::string> m_defines;
    size_t m_uploaded_floats = 0;
    mutable size_t m_triangles_drawn = 0;
    int m_detail = 48;                                 // the tessellation's, of the last load
    GlProgram m_shadow_program, m_shadow_csg_program;  // without and with RT_CSG
    // Light through transparent materials (spec §7.1: every surface on the shadow ray multiplies
    // S_l by its T): per shadow layer, the product of the T of every transparent surface the
    // light's view meets (rgb) and the depth of the nearest one (alpha), at a lower resolution.
    GlProgram m_transmit_program, m_transmit_csg_program;
    GlFramebuffer m_transmit_fbo;
    GlTexture m_transmit_tex;
    int m_transmit_layers = 0;
    bool m_transparent = false;  // some material placed in the scene transmits
    GlFramebuffer m_shadow_fbo;
    GlTexture m_shadow_tex;
    int m_shadow_layers = 0;
    std::vector<ShadowView> m_shadow_views;
    std::optional<SceneTime> m_shadow_time;  // the joints' time the maps were rendered at
    bool m_shadows_valid = false;
    GlProgram m_line_program;
    GlVertexArray m_line_vao;
    GlBuffer m_line_vbo;
    std::vector<SetBuffers> m_sets;
    bool m_csg = false;                 // a placed set has CSG nodes: programs with RT_CSG
    std::vector<GlTexture> m_textures;  // none for a texture no material drawn uses
    std::vector<EnvMap> m_env;
    std::vector<std::vector<int>> m_env_of;  // [instance][range]: its map in m_env, -1: none
                                             // (the objects of a map are left out of it)
    GlFramebuffer m_env_fbo;
    GlRenderbuffer m_env_depth;
    bool m_env_chosen = false, m_env_valid = false, m_env_shadows = false;
    std::optional<SceneTime> m_env_time;  // the scene's time when the maps were chosen
    int m_max_depth = 5;              // the trace's recursion depth, for the hits inside a solid
    bool m_env_ready = false;         // every map has had its first bounce since the scene loaded
    size_t m_env_next = 0;            // the next (bounce * maps + map) to render
    std::vector<Light> m_env_lights;  // what the maps were rendered with
    int m_env_drawn = 0;
};

}  // namespace rt::view
