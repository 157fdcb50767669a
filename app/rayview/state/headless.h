// rayview --headless: the scene rendered without a display. No GL.
#pragma once

#include <optional>
#include <string>

#include "rt/format/parser.h"
#include "rt/render/render.h"

namespace rt::view {

/// Without a display: the same renderer, headless (`spp` samples per pixel, `settings`' size),
/// to SCENE.png in the working directory. With `compare` (--compare), the reference is rendered
/// at that image's size instead and the comparison's figures printed, as the pane's status
/// line says them. Returns the exit code.
int render_headless(const std::string& path, MissingTextures missing = MissingTextures::Error,
                    const RenderSettings& settings = {}, int spp = 16,
                    std::optional<Dialect> dialect = std::nullopt, const std::string& compare = "");

}  // namespace rt::view
