// The kinds of light (spec §3.1; the sphere light of V3, §13.3), shared by the description and the
// render representation so that neither has to include the other.
#pragma once

namespace rt {

/// Sphere: a spherical area light (V3 #light_sphere): point-light terms at its centre, the shadow
/// factor averaged over its surface (spec §13.9).
enum class LightKind { Directional, Point, Spot, Sphere };
inline constexpr int kLightKinds = 4;

}  // namespace rt
