// RenderScene moved to rt/render_scene.h (the compile writes it, accel and render read it). This
// forward stays only for rt/shapes/tessellate.h, whose include goes with tessellate_set's move.
#pragma once

#include "rt/render_scene.h"
