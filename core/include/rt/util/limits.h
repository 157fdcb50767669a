// Every limit of the library, in one place: the resource budget every reader and allocator checks
// before it allocates (a count or a size that a file declares, or that the user asks for, is
// compared with what the file can hold and with this budget first, and refused with a message
// that names the size), and the fixed limits of the parser, the render, the inspector and the
// decoders. Each bounds what a hostile or mistaken input can cost; the messages name the value.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rt {

/// The default largest image, in pixels: 8192 x 8192. It bounds every image the library makes
/// or reads (the render's own, textures, reference images, part files); --max-pixels raises it.
inline constexpr uint64_t kDefaultMaxImagePixels = uint64_t{1} << 26;

/// The largest budget that can be set: 2^40 pixels, far beyond any machine's memory, so that
/// the size checks' products (pixels x channels x bytes) cannot overflow 64 bits.
inline constexpr uint64_t kMaxImagePixelsLimit = uint64_t{1} << 40;

/// The largest file read (scenes, textures, images, parts, configurations): 4 GiB, a text scene of
/// about 50 million triangles. A larger file is refused with its size before anything is read.
inline constexpr uint64_t kMaxFileBytes = uint64_t{4} << 30;
/// How much a file may grow while it is read beyond the size it had when opened (1 MiB): a read
/// past that is refused, so a file whose reads never end cannot take the machine's memory.
inline constexpr uint64_t kMaxFileGrowth = uint64_t{1} << 20;

// The parser's limits (docs/format.md, "Limits"): they keep the recursion of every consumer of
// the group tree and the file tree shallow, and memory bounded by the input's size.

/// Nested #group_begin/#joint_begin in one file: 10000, well past the deepest real scene (1734).
inline constexpr int kMaxGroupDepth = 10000;
/// Nested #ray_file includes: 200 files, each an open file and a level of the include tree's walks.
inline constexpr int kMaxIncludeDepth = 200;
/// File copies placed in the world by instancing (nested instances multiply): 2^20, so that a few
/// small files cannot place billions of copies.
inline constexpr long long kMaxPlacements = 1 << 20;
/// V3 CSG nodes nested inside CSG nodes in one file: 100 (the public V3 scenes nest 1): a hit on a
/// CSG is classified by a walk of its node's whole subtree, so the nesting is a cost per ray.
inline constexpr int kMaxCsgDepth = 100;
/// V3 lists, transforms and CSG nodes nested in one file: 1000 (the public V3 scenes nest 4).
inline constexpr int kMaxV3Depth = 1000;

/// The deepest a ray may be traced (trace_ray's depth, RenderSettings::max_depth, --depth). Each
/// level is a nested call of the shading code: about 1.2 KB of stack in a release build and 6 KB
/// under AddressSanitizer, so 256 levels take 0.3 MB (1.5 MB), well within a worker thread's stack
/// (8 MiB on Linux, 2 MiB on the web page's workers). A deeper request is refused (raytrace and
/// rayview: a usage error; the library: std::invalid_argument) rather than overflowing it.
inline constexpr int kMaxDepth = 256;
/// Points per sphere light (--light-samples): 2^20, as the render's plan holds one direction per
/// point.
inline constexpr int kMaxLightSamples = 1 << 20;
/// Render and load threads (--threads): 256, so that a mistyped count cannot start thousands.
inline constexpr int kMaxThreads = 256;

// The inspector's limits keep a pixel's tree, its memory and its text bounded whatever --depth,
// the scene's lights and its transparent surfaces (a reflected and a refracted ray at each hit
// double the rays each level: one pixel of a 300-byte scene at depth 256 traced 110,000).

/// Rays recorded in a tree (camera, reflected and refracted): 4096.
inline constexpr size_t kMaxInspectRays = 4096;
/// Light terms, shadow rays and occluders recorded in a tree: 65536.
inline constexpr size_t kMaxInspectRecords = 65536;
/// Shadow rays recorded per light term (a sphere light traces up to kMaxLightSamples): 16.
inline constexpr size_t kMaxInspectShadowRays = 16;

/// Scans of a progressive JPEG: 500. Each is a pass over the whole image, so a small file of
/// thousands of them would take minutes (libjpeg-turbo's own fuzzers stop at 500 too).
inline constexpr int kMaxJpegScans = 500;
/// The values (pixels times channels) an EXR file may hold, in channels of the largest image the
/// budget allows: 16 (the render's RGB and its AOVs are 15 at most).
inline constexpr uint64_t kMaxExrChannelsAtBudget = 16;
/// The longest part file header looked through for its end: 1 MiB (its lines are short: 64 blocks
/// at most, one settings line).
inline constexpr size_t kMaxPartHeaderBytes = size_t{1} << 20;

/// The budget in force (process-wide; kDefaultMaxImagePixels until set).
uint64_t max_image_pixels();
/// Sets the budget, clamped to [1, kMaxImagePixelsLimit]; the programs call it from --max-pixels
/// before loading anything.
void set_max_image_pixels(uint64_t pixels);

/// Empty when a `width` x `height` image fits the budget, else why not, naming the size and the
/// flag that raises it: "<what> of 32768x32768 pixels (1073741824) is larger than the budget of
/// 67108864 pixels (8192x8192); --max-pixels raises it". No overflow for any 64-bit input.
std::string image_size_error(uint64_t width, uint64_t height, const std::string& what);
/// The same against a given budget instead of the one in force.
std::string image_size_error(uint64_t width, uint64_t height, const std::string& what,
                             uint64_t budget);

/// The texels that all the textures of one scene may hold together: 4 times the image budget
/// (2^28 by default, a 16384x16384 texture's worth, 768 MB as 8-bit RGB), so that a scene of many
/// small files that each decode to the largest image cannot take the machine's memory.
/// --max-pixels raises both.
uint64_t max_scene_texels();

/// While it lives, every image decoded on this thread must also fit within `pixels` (the scene's
/// textures decode within what its texel budget has left), which the message names as `name`
/// ("what is left of the scene's texture budget (...)"). Scopes nest: the innermost applies.
class DecodeBudget {
public:
    DecodeBudget(uint64_t pixels, std::string name);
    ~DecodeBudget();
    DecodeBudget(const DecodeBudget&) = delete;
    DecodeBudget& operator=(const DecodeBudget&) = delete;

private:
    friend std::string decode_size_error(uint64_t, uint64_t, const std::string&);
    uint64_t m_pixels;
    std::string m_name;
    const DecodeBudget* m_outer;
};

/// The decoders' check before they allocate: image_size_error() against the budget in force,
/// then against this thread's DecodeBudget, if any ("<what> of 8192x8192 pixels (67108864) is
/// larger than what is left of the scene's texture budget (...); --max-pixels raises it").
std::string decode_size_error(uint64_t width, uint64_t height, const std::string& what);

}  // namespace rt
