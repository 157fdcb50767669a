// The script's `light` command on a light's description (script.cpp runs it). No GL.
#pragma once

#include <string>

#include "rt/scene/scene_desc.h"

namespace rt::view {

/// A light edit (the script's `light` command) WHAT (colour: a V0/V1 light's one colour, which sets
/// ambient 0 and diffuse = specular; ambient, diffuse, specular: one of a V3 light's colours;
/// a number of kLightNumbers that the light's kind has, `a` clamped to its range) with
/// arguments (a, b, c). False, and `*l` unchanged, for another WHAT.
bool edit_light(const std::string& what, double a, double b, double c, LightDesc* l);

}  // namespace rt::view
