// Many views of one scene from a file (`rast render --cameras FILE`): turntables,
// camera sweeps and dataset generation render a list of cameras with one
// loaded scene and one renderer. Two formats are read:
//  - a JSON list of objects whose keys are rast's camera flags: "eye",
//    "target", "up" (3 numbers each), "fovy" (degrees), "near", "far"; a key
//    left out keeps the command line's camera (its flags, or the framing);
//  - NeRF's transforms.json: {"camera_angle_x": radians, "frames": [{
//    "transform_matrix": 4x4 camera-to-world, rows first}, ...]}, the camera
//    looking down its -Z with +Y up (OpenGL's convention, as NeRF's Blender
//    scenes); a frame's own "camera_angle_x" wins over the file's.
// Files come from strangers: every malformed entry is one Error naming the
// file, the view and the key.
#pragma once

#include "host/scene/camera.h"

#include <string>
#include <vector>

namespace rast {

// At most this many views in one file (a million views of 1x1 pixels is
// still a reasonable dataset; more is a malformed file).
constexpr size_t kMaxCameraListViews = 1u << 20;

// Parses `text` (the file's contents; `name` only names it in errors).
// `base` gives the values an entry leaves out; width/height the image's
// aspect, which turns NeRF's horizontal angle into rast's vertical fovy.
std::vector<Camera> parseCameraList(const std::string& text, const std::string& name, const Camera& base, int width,
                                    int height);
// Reads the file (at most 256 MiB) and parses it.
std::vector<Camera> loadCameraList(const std::string& path, const Camera& base, int width, int height);

}  // namespace rast
