// The catalogue of mistakes and the teaching render: the shading code of shading_impl.h compiled
// once more, the generic combination, with the recorder WithMistakes (variants.h) whose switches
// the formula sites read; the camera made again with its mistakes (camera.cpp). The output
// stage's mistakes are image.cpp's.
#include "rt/render/mistakes.h"

#include <stdexcept>

#include "shading_impl.h"
#include "variants.h"

namespace rt {

namespace {

using S = MistakeStage;

// In the order of Mistake (checked by mistake_info()).
const std::vector<MistakeInfo> kCatalogue = {
    {Mistake::FullAngle, "full-angle", "§6.1", "tan_h = tan(ha)", "tan_h = tan(ha / 2)",
     "the camera's half-height angle read as the full angle: the view zoomed in", S::Camera},
    {Mistake::AngleOnWidth, "angle-on-width", "§6.1", "tan_h = tan(ha), tan_w = aspect·tan_h",
     "tan_w = tan(ha), tan_h = tan(ha) / aspect",
     "the angle applied to the width: a wide image zoomed in", S::Camera},
    {Mistake::AngleDegrees, "angle-degrees", "§6.1", "tan_h = tan(ha), ha in radians",
     "tan_h = tan(ha·π/180)",
     "the camera's angle, in radians, converted as if in degrees: a "
     "tiny view, zoomed in far",
     S::Camera},
    {Mistake::FlipVertical, "flip-vertical", "§6.2, §9",
     "image row 0 = pixel row j = 0 = the top of the view", "row j written as row H−1−j",
     "the rows written bottom-up: the image upside down", S::Output},
    {Mistake::Gamma, "gamma", "§9", "byte = ⌊255·c' + 0.5⌋, no gamma",
     "byte = ⌊255·c'^(1/2.2) + 0.5⌋", "a 1/2.2 gamma applied before the 8 bits: a washed-out image",
     S::Output},
    {Mistake::Bgr, "bgr", "§9", "bytes in the order R, G, B", "bytes in the order B, G, R",
     "the red and blue channels swapped", S::Output},
    {Mistake::WrapOverflow, "wrap-overflow", "§9", "c' = clamp(c, 0, 1); byte = ⌊255·c' + 0.5⌋",
     "byte = ⌊255·c + 0.5⌋ mod 256 (no clamp)",
     "no clamp before the 8 bits: bright areas wrap round to dark", S::Output},
    {Mistake::NoAmbient, "no-ambient", "§7.1", "C = K_E + (K_A ⊙ t) ⊙ A + …",
     "C = K_E + … (and no light's ambient term in V3)",
     "the ambient term left out: unlit parts black", S::Shading},
    {Mistake::NoEmissive, "no-emissive", "§7.1", "C = K_E + (K_A ⊙ t) ⊙ A + …",
     "C = (K_A ⊙ t) ⊙ A + …", "the emissive colour left out: glowing objects dark", S::Shading},
    {Mistake::NoDiffuseClamp, "no-diffuse-clamp", "§7.1", "Σ over the lights with N·L > 0",
     "Σ over every light, N·L ≤ 0 too",
     "lights behind the surface still add K_D (N·L) < 0: they darken it", S::Shading},
    {Mistake::OneSided, "one-sided", "§5", "N = n_s turned to face the ray (d·n_g > 0: −n_s)",
     "N = n_s always", "no two-sided rule: the back of a surface shaded with the normal away",
     S::Shading},
    {Mistake::NoSpecular, "no-specular", "§7.1", "… + K_S · spec_l", "spec_l = 0",
     "the highlight term left out: no highlights (reflections stay)", S::Shading},
    {Mistake::Blinn, "blinn", "§7.1", "spec_l = (R_v·L)^e, R_v = d − 2(d·N)N",
     "spec_l = (N·H)^e, H = normalize(L − d)",
     "Blinn's half vector for Phong's mirror vector: wider highlights", S::Shading},
    {Mistake::LightDirReversed, "light-dir-reversed", "§7.2",
     "directional light: L = −normalize(dir)", "L = normalize(dir)",
     "a directional light's direction of travel taken as L: lit from behind", S::Shading},
    {Mistake::NoAttenuation, "no-attenuation", "§7.2", "I_l = colour / (ca + la·dist + qa·dist²)",
     "I_l = colour", "a point or spot light's colour not attenuated with distance", S::Shading},
    {Mistake::SpotNoDropoff, "spot-no-dropoff", "§7.2",
     "I_l = colour · max(0, cos_a)^p / (ca + la·dist + qa·dist²)",
     "I_l = colour / (ca + la·dist + qa·dist²)",
     "the spot's drop-off left out: a flat disc of light", S::Shading},
    {Mistake::SpotCutoffFullAngle, "spot-cutoff-full-angle", "§7.2", "0 if acos(cos_a) > cutoff",
     "0 if acos(cos_a) > cutoff / 2",
     "the spot's cut-off read as the full cone angle: a smaller spot", S::Shading},
    {Mistake::NoShadows, "no-shadows", "§7.2", "S_l from a shadow ray toward the light",
     "S_l = (1, 1, 1)", "no shadow rays: no shadows", S::Shading},
    {Mistake::OpaqueShadows, "opaque-shadows", "§7.2",
     "every surface hit on the shadow ray multiplies S_l by its T", "any hit gives S_l = 0",
     "transparent objects cast full black shadows", S::Shading},
    {Mistake::ShadowPastLight, "shadow-past-light", "§7.2",
     "the shadow ray ends at the light (length dist)", "the shadow ray goes on past the light",
     "objects beyond a point light shadow what it lights", S::Shading},
    {Mistake::NoOffset, "no-offset", "§7.5",
     "shadow, reflected and refracted rays start at P + s·δ·n_g", "they start at P",
     "secondary rays hit their own surface: shadow acne", S::Shading},
    {Mistake::NoReflection, "no-reflection", "§7.1, §7.4", "… + K_S ⊙ trace(reflected ray)",
     "no reflected ray", "mirrors show no reflection", S::Shading},
    {Mistake::NoRefraction, "no-refraction", "§7.1, §7.4", "… + T ⊙ trace(refracted ray)",
     "no refracted ray", "transparent objects show nothing through them", S::Shading},
    {Mistake::IorInverted, "ior-inverted", "§7.4", "η = 1/refind entering, refind leaving",
     "η = refind entering, 1/refind leaving",
     "the index of refraction inverted: glass bends light the wrong way", S::Shading},
    {Mistake::DepthOffByOne, "depth-off-by-one", "§8", "children traced only when depth − 1 ≥ 1",
     "children traced when depth − 1 ≥ 0", "one bounce more than the depth allows", S::Shading},
    {Mistake::NoCutoff, "no-cutoff", "§8", "a child ray traced only when max(weight) ≥ cutoff",
     "every child ray traced", "the path-weight cutoff ignored: faint reflections traced",
     S::Shading},
    {Mistake::TextureVFlipped, "texture-v-flipped", "§7.3", "y = (1 − v')·H_t − 0.5",
     "y = v'·H_t − 0.5", "v not flipped: textures upside down", S::Shading},
    {Mistake::TextureDiffuseOnly, "texture-diffuse-only", "§7.3",
     "C = K_E + (K_A ⊙ t) ⊙ A + … (K_D ⊙ t)·(N·L)", "C = K_E + K_A ⊙ A + … (K_D ⊙ t)·(N·L)",
     "the texel multiplies K_D only, not K_A: untextured ambient", S::Shading},
};

// The plan of a teaching render: the caller's, with the camera made again with the mistakes and
// the shading code that reads them. The trace gets the plan by reference, and finds its
// mistakes beside it: a MistakenPlan never leaves this file, and render_samples() hands the very
// object it was given down to the trace (a copy sliced to a RenderPlan would lose them).
struct MistakenPlan : RenderPlan {
    MistakeSet mistakes;
};

Vec3 mistaken_trace(const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, const Ray& ray, int depth, const Vec3& weight,
                    RayCounters& counters, Rng* rng, shading::NoRecord) {
    shading::WithMistakes rec;
    rec.mistakes = static_cast<const MistakenPlan&>(plan).mistakes;
    return shading::trace<kShadeAll>(scene, plan, settings, ray, depth, weight, counters, rng, rec);
}

constexpr ShadingVariant kMistakenShading{&mistaken_trace};

MistakenPlan mistaken_plan(const RenderScene& scene, const RenderPlan& plan,
                           const MistakeSet& mistakes) {
    MistakenPlan p;
    static_cast<RenderPlan&>(p) = plan;
    p.mistakes = mistakes;
    p.shading = &kMistakenShading;
    const Camera& c = plan.camera;
    p.camera = make_camera(
        scene.camera ? *scene.camera : default_camera(scene.world_bounds, c.width, c.height),
        c.width, c.height, mistakes);
    return p;
}

}  // namespace

const std::vector<MistakeInfo>& mistake_catalogue() { return kCatalogue; }

const MistakeInfo& mistake_info(Mistake m) {
    const MistakeInfo& info = kCatalogue.at(static_cast<size_t>(m));
    if (info.mistake != m) throw std::logic_error("the catalogue is out of the order of Mistake");
    return info;
}

std::optional<Mistake> find_mistake(std::string_view name) {
    for (const MistakeInfo& info : kCatalogue)
        if (name == info.name) return info.mistake;
    return std::nullopt;
}

const char* stage_name(MistakeStage stage) {
    switch (stage) {
        case MistakeStage::Camera:
            return "camera";
        case MistakeStage::Shading:
            return "shading";
        case MistakeStage::Output:
            return "output";
    }
    return "?";
}

bool MistakeSet::touches(MistakeStage stage) const {
    for (Mistake m : list())
        if (mistake_info(m).stage == stage) return true;
    return false;
}

std::vector<Mistake> MistakeSet::list() const {
    std::vector<Mistake> out;
    for (int i = 0; i < kMistakeCount; ++i)
        if (has(static_cast<Mistake>(i))) out.push_back(static_cast<Mistake>(i));
    return out;
}

std::string MistakeSet::names() const {
    std::string s;
    for (Mistake m : list()) s += (s.empty() ? "" : ", ") + std::string(mistake_info(m).name);
    return s;
}

MistakeSet parse_mistakes(const std::vector<std::string>& names) {
    MistakeSet set;
    for (const std::string& list : names) {
        size_t start = 0;
        while (start <= list.size()) {
            const size_t end = std::min(list.find(',', start), list.size());
            const std::string name = list.substr(start, end - start);
            const std::optional<Mistake> m = find_mistake(name);
            if (!m)
                throw std::invalid_argument("unknown mistake '" + name +
                                            "' (the catalogue: raytrace --mistake list)");
            set.add(*m);
            start = end + 1;
        }
    }
    return set;
}

bool render_with_mistakes(RenderState& state, const RenderScene& scene, const RenderPlan& plan,
                          const RenderSettings& settings, const MistakeSet& mistakes, int spp,
                          const ProgressFn& progress, const std::atomic<bool>* stop) {
    const MistakenPlan p = mistaken_plan(scene, plan, mistakes);
    return render_samples(state, scene, p, settings, spp, progress, stop);
}

Image render_with_mistakes(const RenderScene& scene, const RenderPlan& plan,
                           const RenderSettings& settings, const MistakeSet& mistakes, int spp) {
    RenderState state;
    render_with_mistakes(state, scene, plan, settings, mistakes, spp);
    return state.image();
}

Image render_written(const RenderScene& scene, const RenderPlan& plan,
                     const RenderSettings& settings, const MistakeSet& mistakes, int spp) {
    return as_written(render_with_mistakes(scene, plan, settings, mistakes, spp), mistakes);
}

}  // namespace rt
