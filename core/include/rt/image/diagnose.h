// The diagnosis of a mistaken image: which of the catalogue's mistakes
// (docs/mistakes.md) best explain how a student's image differs from the reference, ranked,
// each with the share of the difference it explains. The cheap global fits come first
// (rt/image/fit.h); then the reference rendered with each mistake switched on (the renderer's
// own code: rt/render/mistakes.h), and, when one explains only part, with a second one too.
// The renders come through a callback, made once per set of mistakes (MutantRenders), so a
// class of images of one size renders each mutant once.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rt/image/image.h"

namespace rt {

/// The reference rendered with a set of mistakes on (none: the reference itself), each set
/// rendered once: the renders of one scene at one size.
class MutantRenders {
public:
    using Render = std::function<Image(const std::vector<std::string>& mistakes)>;
    explicit MutantRenders(Render render) : m_render(std::move(render)) {}
    /// The image with `mistakes` on (in the order given; a set is one render whatever its order).
    const Image& get(std::vector<std::string> mistakes);
    size_t renders() const { return m_images.size(); }

private:
    Render m_render;
    std::map<std::vector<std::string>, std::unique_ptr<Image>> m_images;
};

/// One explanation: a mistake (or two at once), and how well it explains the image.
struct Explanation {
    std::vector<std::string> mistakes;  // catalogue names
    std::string detail;                 // a global fit's parameter ("exponent 2.2"), else ""
    /// 1 - error after / error before (mean squared, 8-bit steps), pixel by pixel or over 4x4
    /// blocks' means, whichever is larger (a speckle explained on average).
    double explained = 0;
    Image mutant;  // the reference as the mistake makes it, to show beside the image
    /// "no-shadows", "gamma (exponent 2.2)", "no-shadows + gamma".
    std::string name() const;
};

struct DiagnoseSettings {
    double enough = 0.6;      // below this share, no mistake is named ("none ... explains")
    double pair_below = 1.0;  // the best single explanation below this: pairs are tried
    int pair_candidates = 3;  // the mutants that explain most, paired with every mistake
    int ranked = 3;           // explanations kept
    double half_angle = 0.0;  // the camera's half-height angle (to name a zoom; 0: unnamed)
};

struct Diagnosis {
    std::vector<Explanation> ranked;  // best first; empty: none explains enough
    double error_before = 0;          // the image against the reference
    /// "none of the known mistakes explains this image", or the ranked names with their shares.
    std::string summary() const;
};

/// Diagnoses `image` (as its file holds it: bytes / 255) against the reference renders of its
/// scene at its size, trying every mistake of `catalogue`. The caller diagnoses only images that
/// fail its comparison rule (a passing image gets no diagnosis).
Diagnosis diagnose(const Image& image, MutantRenders& renders,
                   const std::vector<std::string>& catalogue, const DiagnoseSettings& settings);

}  // namespace rt
