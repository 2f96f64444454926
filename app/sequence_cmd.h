// `rast render --frames START:END:FPS` and `--turntable N`: a sequence of
// frames from one renderer (the scene uploaded once, each frame's pose sent as
// matrices and moved vertices), written as numbered images (-o out_%04d.png)
// or piped to ffmpeg as a video (-o out.mp4, .webm, .gif; docs/animation.md).
#pragma once

#include "app/cli_options.h"

#include <string>

namespace rast {

struct SequenceOptions {
  std::string frames;  // "START:END:FPS", empty: one time (--time, or the rest pose)
  int turntable = 0;   // frames of one orbit of the camera around its target, 0: none

  bool wanted() const { return !frames.empty() || turntable > 0; }
};

// The frame times of "START:END:FPS": START, START + 1/FPS, ... up to END
// (inclusive, to a millionth of a frame). Throws Error for a malformed spec.
std::vector<double> frameTimes(const std::string& spec, double* fps);

int runSequence(const SceneOptions& so, const SequenceOptions& seq, const std::string& out);

}  // namespace rast
