// The instruction set the ray kernels run with. The library is built for baseline x86-64 (and
// WebAssembly's 128-bit SIMD on the web); its hot kernels (the BVH walks, the triangle blocks)
// are compiled once more for AVX2 and for AVX-512 (core/src/accel/isa_target.h), and the widest
// one the CPU runs is picked once, at the first query. The environment variable RAYTRACER_ISA
// (sse2, avx2 or avx512) forces one. Every image is the same bit for bit under each.
#pragma once

#include <string>
#include <vector>

namespace rt {

enum class Isa { Sse2, Avx2, Avx512 };
inline constexpr int kIsaCount = 3;

/// "sse2", "avx2", "avx512".
const char* isa_name(Isa isa);

/// The instruction sets this build has kernels for and this CPU can run, narrowest first.
std::vector<Isa> supported_isas();

/// The one the kernels use: RAYTRACER_ISA when it is set, else the widest supported. Chosen at
/// the first call; throws SceneError (no location) when RAYTRACER_ISA names an unknown
/// instruction set or one this CPU cannot run, and again at every later call.
Isa active_isa();

/// Why RAYTRACER_ISA cannot be honoured ("RAYTRACER_ISA=x: ..."), or empty when it can. The
/// programs check this first and stop with the message.
const std::string& isa_error();

/// What --version and --stats print: "avx2 (this CPU runs sse2, avx2, avx512)", and whether
/// RAYTRACER_ISA chose it.
std::string isa_summary();

}  // namespace rt
