// rayview --headless: the scene rendered without a display. No GL.
#pragma once

#include <optional>
#include <string>

#include "rt/format/parser.h"
#include "rt/render/render.h"

namespace rt::view {

/// Without a display: the same renderer, headless (`spp` samples per pixel, `settings`' size),
/// to SCENE.png in the working directory. Returns the exit code.
int render_headless(const std::string& path, MissingTextures missing = MissingTextures::Error,
                    const RenderSettings& settings = {}, int spp = 16,
                    std::optional<Dialect> dialect = std::nullopt);

}  // namespace rt::view
