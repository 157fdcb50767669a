// The three kinds of light (spec §3.1), shared by the description and the render representation
// so that neither has to include the other.
#pragma once

namespace rt {

enum class LightKind { Directional, Point, Spot };

}  // namespace rt
