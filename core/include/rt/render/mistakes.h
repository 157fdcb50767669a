// The catalogue of typical mistakes (docs/mistakes.md): each one a formula of the
// spec got wrong the way students get it wrong, and each one a switch of the renderer's own code
// (the camera in camera.cpp, the shading in shading_impl.h, the 8-bit output in image.cpp), so a
// mistaken image is rendered by the very code that renders the right one. The normal render
// compiles the switches away (its recorder, NoRecord, knows no mistakes); render_with_mistakes()
// runs the generic shading once more with them on, as the inspector does with its recorder.
// Teaching only: what it renders is not the spec's image.
#pragma once

#include <atomic>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rt/image/image.h"
#include "rt/render/camera.h"
#include "rt/render/render.h"

namespace rt {

/// A mistake of the catalogue (mistake_catalogue() holds them in this order).
enum class Mistake : uint8_t {
    FullAngle,            // §6.1 tan_h = tan(ha / 2)
    AngleOnWidth,         // §6.1 tan_w = tan(ha), tan_h = tan(ha) / aspect
    AngleDegrees,         // §6.1 tan_h = tan(ha·π/180): radians read as degrees
    FlipVertical,         // §9 rows bottom-up
    Gamma,                // §9 byte of c^(1/2.2)
    Bgr,                  // §9 red and blue swapped
    WrapOverflow,         // §9 no clamp: the byte wraps mod 256
    NoAmbient,            // §7.1 no K_A ⊙ t ⊙ A
    NoEmissive,           // §7.1 no K_E
    NoDiffuseClamp,       // §7.1 lights with N·L <= 0 add too
    OneSided,             // §5 no two-sided rule
    NoSpecular,           // §7.1 no K_S spec_l
    Blinn,                // §7.1 (N·H)^e for (R_v·L)^e
    LightDirReversed,     // §7.2 L = dir for a directional light
    NoAttenuation,        // §7.2 no 1 / (ca + la d + qa d²)
    SpotNoDropoff,        // §7.2 no max(0, cos_a)^p
    SpotCutoffFullAngle,  // §7.2 acos(cos_a) > cutoff / 2
    NoShadows,            // §7.2 S_l = 1
    OpaqueShadows,        // §7.2 any hit: S_l = 0
    ShadowPastLight,      // §7.2 shadow rays not stopped at a point light
    NoOffset,             // §7.5 secondary rays from P itself
    NoReflection,         // §7.1/§7.4 no reflected ray
    NoRefraction,         // §7.1/§7.4 no refracted ray
    IorInverted,          // §7.4 η = refind entering, 1/refind leaving
    DepthOffByOne,        // §8 children traced while depth - 1 >= 0
    NoCutoff,             // §8 the path-weight cutoff ignored
    TextureVFlipped,      // §7.3 y = v·H_t - 0.5 (row 0 at v = 0)
    TextureDiffuseOnly,   // §7.3 the texel multiplies K_D only
};
inline constexpr int kMistakeCount = static_cast<int>(Mistake::TextureDiffuseOnly) + 1;

/// Which part of the renderer a mistake switches.
enum class MistakeStage { Camera, Shading, Output };

/// One entry of the catalogue.
struct MistakeInfo {
    Mistake mistake;
    const char* name;         // kebab-case, as docs/mistakes.md and raytrace --mistake spell it
    const char* section;      // of the spec: "§7.2"
    const char* formula;      // the spec's formula it breaks
    const char* instead;      // what the mistaken code computes instead
    const char* description;  // one line a student reads
    MistakeStage stage;
};

/// The catalogue, in the order of Mistake.
const std::vector<MistakeInfo>& mistake_catalogue();
const MistakeInfo& mistake_info(Mistake m);
/// The mistake named `name` (its kebab-case name), or nullopt.
std::optional<Mistake> find_mistake(std::string_view name);
/// "camera", "shading" or "output".
const char* stage_name(MistakeStage stage);

/// A set of mistakes switched on at once.
class MistakeSet {
public:
    MistakeSet() = default;
    MistakeSet(std::initializer_list<Mistake> mistakes) {
        for (Mistake m : mistakes) add(m);
    }
    bool has(Mistake m) const { return (m_bits >> static_cast<int>(m)) & 1u; }
    void add(Mistake m) { m_bits |= uint64_t{1} << static_cast<int>(m); }
    bool empty() const { return m_bits == 0; }
    /// Some mistake of the set touches `stage`.
    bool touches(MistakeStage stage) const;
    /// The mistakes, in the catalogue's order.
    std::vector<Mistake> list() const;
    /// Their names joined by ", ".
    std::string names() const;
    bool operator==(const MistakeSet&) const = default;

private:
    uint64_t m_bits = 0;
};

/// The set of the named mistakes (names may also be comma-separated lists). Throws
/// std::invalid_argument for an unknown name ("unknown mistake 'x'"), naming the catalogue.
MistakeSet parse_mistakes(const std::vector<std::string>& names);

/// The camera of spec §6.1 with the camera's mistakes of `mistakes` (full-angle, angle-on-width;
/// camera.cpp): make_camera(pose, width, height) when it has none.
Camera make_camera(const CameraPose& pose, int width, int height, const MistakeSet& mistakes);

/// Adds `spp` samples per pixel to `state` as render_samples() does (the same sample positions
/// and random numbers), with the camera and shading mistakes of `mistakes` on: the plan's camera
/// made again with them, and the generic shading code run with a switch per formula. `plan` is
/// make_render_plan(scene, settings). The output stage's mistakes apply when the image is written
/// (to_bytes(image, mistakes), as_written()). Returns false when stopped.
bool render_with_mistakes(RenderState& state, const RenderScene& scene, const RenderPlan& plan,
                          const RenderSettings& settings, const MistakeSet& mistakes, int spp,
                          const ProgressFn& progress = {}, const std::atomic<bool>* stop = nullptr);

/// The linear image of render_with_mistakes() on a fresh state (`spp` samples per pixel).
Image render_with_mistakes(const RenderScene& scene, const RenderPlan& plan,
                           const RenderSettings& settings, const MistakeSet& mistakes, int spp = 1);

/// What a program with `mistakes` writes to an 8-bit file, read back (bytes / 255):
/// as_written(render_with_mistakes(...), mistakes). With no mistake, the right image as its PNG
/// holds it. The diagnosis's mutant references (rt/image/diagnose.h) are these.
Image render_written(const RenderScene& scene, const RenderPlan& plan,
                     const RenderSettings& settings, const MistakeSet& mistakes, int spp = 1);

/// The 8 bits of spec §9 (c' = clamp(c, 0, 1); byte = floor(255 c' + 0.5)), row 0 at the top, with
/// the output stage's mistakes of `mistakes` (gamma, bgr, wrap-overflow, flip-vertical; image.cpp):
/// to_bytes(image) when it has none.
std::vector<uint8_t> to_bytes(const Image& image, const MistakeSet& mistakes);

/// The image as an 8-bit file written with `mistakes` holds it, read back (byte / 255): what a
/// student's program with those output mistakes writes. Saved as PNG, BMP or PPM it gives the
/// very bytes of to_bytes(image, mistakes).
Image as_written(const Image& image, const MistakeSet& mistakes);

}  // namespace rt
