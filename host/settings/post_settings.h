// What the post-processing chain is asked to do (RenderSettings::post). With
// everything at its default no pass runs, the frame never exists in float, and
// shading packs RGBA8 directly, exactly as before the chain existed.
#pragma once

#include <string>

namespace rast {

// Neutral: Khronos PBR Neutral, the glTF Sample Renderer's default.
enum class ToneMap { None, Reinhard, Aces, Neutral };

struct PostSettings {
  float exposure = 0.0f;            // EV: linear colour times 2^EV
  ToneMap tonemap = ToneMap::None;  // applied after exposure and bloom
  bool bloom = false;
  float bloomThreshold = 1.0f;  // luminance (after exposure) below which nothing blooms
  float bloomStrength = 0.5f;   // weight of the blurred bright pass added back
  int bloomRadius = 16;         // Gaussian radius in full-resolution pixels (blurred at half resolution)
  bool ssao = false;
  float ssaoRadius = 0.0f;  // world units; 0: 5% of the camera's distance to its target
  int ssaoSamples = 8;      // hemisphere directions per pixel after the blur (1..256): each pixel marches a quarter, in 4 steps
  bool floatOutput = false;  // keep the frame in float for an HDR file (-o out.pfm)

  bool anyPass() const { return exposure != 0.0f || tonemap != ToneMap::None || bloom || ssao; }
  // The float film (FrameBuffers::post.hdr) is used: shading writes linear float.
  bool needsFloat() const { return anyPass() || floatOutput; }
};

const char* toString(ToneMap t);
ToneMap parseToneMap(const std::string& s);  // none|reinhard|aces|pbr-neutral; throws Error
// Command-line values: "" keeps the defaults; "T[,S[,R]]" and "R[,N]".
void parseBloom(const std::string& s, PostSettings& p);
void parseSsao(const std::string& s, PostSettings& p);
// Checks ranges; throws Error.
void validate(const PostSettings& p);

}  // namespace rast
