// The kinds of light (spec §3.1; the sphere light of V3, §13.3), shared by the description and the
// render representation so that neither has to include the other, and their names, spelled here
// only.
#pragma once

#include <optional>
#include <string_view>

#include "rt/util/enum_names.h"

namespace rt {

/// Sphere: a spherical area light (V3 #light_sphere): point-light terms at its centre, the shadow
/// factor averaged over its surface (spec §13.9).
enum class LightKind { Directional, Point, Spot, Sphere };
inline constexpr int kLightKinds = 4;

/// "directional", "point", "spot", "sphere" (the inspector's, the reports', the viewer's).
inline constexpr const char* kLightKindNames[kLightKinds] = {"directional", "point", "spot",
                                                             "sphere"};
constexpr const char* light_kind_name(LightKind k) { return enum_name(k, kLightKindNames); }

/// The kind a name of light_kind_name() names; none for another word.
constexpr std::optional<LightKind> light_kind_from_name(std::string_view name) {
    for (int k = 0; k < kLightKinds; ++k)
        if (name == kLightKindNames[k]) return static_cast<LightKind>(k);
    return std::nullopt;
}

}  // namespace rt
