// Built-in scenes for glTF alpha modes (docs/transparency.md): stacks of BLEND
// layers over an opaque backdrop, and a MASK cut-out. Registered in the
// stress table (stress_scenes.cpp) as builtin:layers and builtin:cutout.
#pragma once

#include "host/scene/scene.h"

#include <map>
#include <string>

namespace rast {

// ?n= layers (0..4096, default 8; 0: the backdrop alone, the opaque frame), alpha= (each layer's baseColorFactor.a, any
// finite value: out-of-range ones test clamping; default 0.5), mixed=1 (alphas
// 0.2..0.9 and hues instead of one blue), unlit=0|1 (KHR_materials_unlit,
// default 1), back=0|1 (the opaque red backdrop, default 1), order=back|front
// (submission order: back-to-front or front-to-back), cross=1 (each layer
// tilted so that neighbours intersect), equal=1 (every layer at one depth),
// near_alpha= (the nearest layer's alpha: a strong layer in front).
Scene transparencyLayers(const std::map<std::string, std::string>& p);
// A green MASK quad whose COLOR_0 alpha runs 0 -> 1 left to right, over an
// opaque red backdrop; ?cutoff= (default 0.5), blend=1 draws it BLEND instead.
Scene transparencyCutout(const std::map<std::string, std::string>& p);

}  // namespace rast
