// An image compared with the reference render of its scene (raycompare; rayview's comparison):
// the mean absolute difference, the share of pixels off by more than a tolerance, the largest
// difference and where, and each pixel's difference for a heat map. 8-bit images are compared
// with the reference as an 8-bit file of it holds it (spec §9's rounding), linear ones (PFM, EXR)
// with its linear values; differences are on the 0-255 scale of one 8-bit step either way, and
// relative to the reference's value where it is brighter than white (linear images only: a
// highlight of 20 off by 1 is 12.75 steps off, not 255).
#pragma once

#include <vector>

#include "rt/image/image.h"

namespace rt {

struct CompareSettings {
    /// A pixel is off when one of its channels differs by more than this, in 8-bit steps.
    double tolerance = 8.0;
    /// On an edge of the reference (where its 3x3 neighbourhood of the pixel spans more than the
    /// tolerance in some channel), a pixel's difference is the smallest over that neighbourhood,
    /// taken only from a neighbour whose move (the reference shifted by a pixel) fits the
    /// image's whole 3x3 block there within the tolerance, so that an edge shifted by up to a
    /// pixel is not an error; elsewhere (flat shading) and where no move fits (a highlight made
    /// broader, whose flank is less steep) the pixel's own, so that such a mistake is not
    /// excused.
    bool neighbourhood = false;
    /// The lossy rule (JPEG): each pixel's difference is that of the 3x3 means of both images
    /// around it (clipped at the border), which averages out a JPEG's block noise and ringing
    /// while a real mistake, which changes a region, stays. The neighbourhood is not used with it
    /// (the means already take in a shifted edge's pixel). See docs/tools.md for its numbers.
    bool lossy = false;
    /// The image holds linear values (PFM, EXR): compared unclamped, else through to_byte().
    bool linear = false;
};

struct ImageComparison {
    int width = 0, height = 0;
    Vec3 mean_abs{0.0};        // per channel, in 8-bit steps
    double share_off = 0;      // of the pixels, off by more than the tolerance in some channel
    double max_diff = 0;       // the largest difference of one channel, in 8-bit steps
    int max_x = 0, max_y = 0;  // where it is (the first such pixel, row by row)
    /// Per pixel, row-major from the top: its largest channel difference, in 8-bit steps.
    std::vector<float> error;
    /// Per pixel, the same order: the image's brightness against the reference's (the mean of
    /// its channels' signed differences, in 8-bit steps): > 0 added light, < 0 missing light.
    std::vector<float> signed_error;
    double mean() const { return (mean_abs.x + mean_abs.y + mean_abs.z) / 3.0; }
};

/// Compares `image` with `reference` (the same size, else std::invalid_argument naming both).
ImageComparison compare_images(const Image& image, const Image& reference,
                               const CompareSettings& settings);

/// A false-colour heat map of a comparison's differences: black for none, through blue, green
/// and yellow, to red at `scale` 8-bit steps and beyond (0: the comparison's largest, at least
/// 1). Linear values in [0, 1], for save_image.
Image heat_map(const ImageComparison& c, double scale = 0);

/// The signed view of a comparison: added light (the image brighter than the reference) in
/// orange, missing light (darker) in blue, black for none, full at `scale` 8-bit steps and beyond
/// (0: the comparison's largest, at least 1). Linear values in [0, 1], for save_image.
Image signed_map(const ImageComparison& c, double scale = 0);

/// The signed view's colour at t in [-1, 1] (its scale bar): blue for -1, black for 0, orange
/// for 1.
Vec3 signed_colour(double t);

/// The threshold view: pixels off by more than `tolerance` 8-bit steps in red over the
/// reference dimmed to grey (so that the scene stays recognisable). Linear values in [0, 1].
Image threshold_map(const ImageComparison& c, const Image& reference, double tolerance);

/// The colour of the heat map at t in [0, 1] (its scale bar).
Vec3 heat_colour(double t);

}  // namespace rt
