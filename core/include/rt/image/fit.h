// The cheap global fits of a diagnosis: before any mutant reference is rendered, an
// image that differs from its reference everywhere is tried against what a student's output or
// camera code does to a whole image: a brightness scale, a transfer curve (gamma), a flip, a
// swap of channels, a zoom about the centre (a camera angle read wrongly). Each fit has one
// parameter at most, found by a search over the error; each says how much of the difference it
// explains. The reference is the renderer's linear image; the image is as its file holds it
// (8-bit values / 255), and both are compared as 8-bit files hold them (spec §9).
#pragma once

#include <string>
#include <vector>

#include "rt/image/image.h"

namespace rt {

enum class FitKind { Scale, Gamma, FlipVertical, FlipHorizontal, Channels, Zoom };

/// One global change of an image, and its parameter.
struct GlobalFit {
    FitKind kind = FitKind::Scale;
    /// Scale: the factor on the linear values; Gamma: the exponent g of c^(1/g); Zoom: the
    /// magnification about the image's centre (2: the student's view is half as wide).
    double value = 1.0;
    int channels[3] = {0, 1, 2};  // Channels: output channel k holds input channel channels[k]
};

/// The reference as the change would show it (linear values; a zoom samples it bilinearly, its
/// edge repeated where a zoom out would show what the reference does not hold).
Image apply_fit(const Image& reference, const GlobalFit& fit);

/// A fit, and how well it explains the image.
struct FitResult {
    GlobalFit fit;
    /// The catalogue's name for it (docs/mistakes.md) when it is one ("gamma", "flip-vertical",
    /// "bgr"), else a name of its own ("brightness", "flip-horizontal", "channels gbr", "zoom").
    std::string name;
    std::string detail;       // its parameter, for a reader: "exponent 2.2", "x 0.5", ...
    double error_before = 0;  // mean squared difference in 8-bit steps, image against reference
    double error_after = 0;   // image against the fitted reference (the same pixels)
    /// The share of the difference the fit explains: 1 - after / before (0 when none).
    double explained() const { return error_before > 0 ? 1.0 - error_after / error_before : 0.0; }
};

/// Every kind of fit of `image` to `reference` (the same size, else std::invalid_argument), each
/// with its best parameter, best explained first. A fit that changes nothing (a scale of 1, the
/// identity's channels) is not listed.
std::vector<FitResult> fit_global(const Image& reference, const Image& image);

/// The catalogue's name for a zoom by `k` of a view of half-height angle `half_angle` (radians)
/// and aspect W/H: "full-angle" (the angle read as the full one: k = tan(ha) / tan(ha/2)),
/// "angle-on-width" (the angle applied to the width: k = aspect), or "" for neither (within 3%).
std::string zoom_mistake(double k, double half_angle, double aspect);

/// The mean squared difference, in 8-bit steps, of `image` against `reference` as 8-bit files
/// hold them (the same size).
double mean_squared_bytes(const Image& reference, const Image& image);

}  // namespace rt
