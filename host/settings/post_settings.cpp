#include "host/settings/post_settings.h"

#include "host/settings/render_settings.h"  // parseFiniteList
#include "base/error.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace rast {
namespace {

std::vector<double> numbers(const std::string& s, const char* flag, size_t maxN) {
  std::vector<double> v;
  if (!parseFiniteList(s, v))
    throw Error(std::string(flag) + ": '" + s + "' is not a list of finite numbers (its optional values attach with '=', " +
                flag + "=1,2; a scene file goes before " + flag + ")");
  if (v.size() > maxN) throw Error(std::string(flag) + ": at most " + std::to_string(maxN) + " numbers, got '" + s + "'");
  return v;
}

}  // namespace

const char* toString(ToneMap t) {
  switch (t) {
    case ToneMap::None: return "none";
    case ToneMap::Reinhard: return "reinhard";
    case ToneMap::Aces: return "aces";
    case ToneMap::Neutral: return "pbr-neutral";
  }
  return "none";
}

ToneMap parseToneMap(const std::string& s) {
  if (s == "none") return ToneMap::None;
  if (s == "reinhard") return ToneMap::Reinhard;
  if (s == "aces") return ToneMap::Aces;
  if (s == "pbr-neutral") return ToneMap::Neutral;
  throw Error("unknown tone map '" + s + "' (expected none|reinhard|aces|pbr-neutral)");
}

void parseBloom(const std::string& s, PostSettings& p) {
  p.bloom = true;
  const auto v = numbers(s, "--bloom", 3);
  if (v.size() > 0) p.bloomThreshold = float(v[0]);
  if (v.size() > 1) p.bloomStrength = float(v[1]);
  if (v.size() > 2) {
    if (v[2] != std::floor(v[2])) throw Error("--bloom: the radius is a whole number of pixels");
    p.bloomRadius = int(v[2]);
  }
}

void parseSsao(const std::string& s, PostSettings& p) {
  p.ssao = true;
  const auto v = numbers(s, "--ssao", 2);
  if (v.size() > 0) p.ssaoRadius = float(v[0]);
  if (v.size() > 1) {
    if (v[1] != std::floor(v[1])) throw Error("--ssao: the sample count is a whole number");
    p.ssaoSamples = int(v[1]);
  }
}

void validate(const PostSettings& p) {
  if (!(p.exposure >= -32.0f && p.exposure <= 32.0f)) throw Error("--exposure must be in [-32, 32] EV");
  if (!(p.bloomThreshold >= 0.0f)) throw Error("--bloom: the threshold must be >= 0");
  if (!(p.bloomStrength >= 0.0f && p.bloomStrength <= 100.0f)) throw Error("--bloom: the strength must be in [0, 100]");
  if (p.bloomRadius < 2 || p.bloomRadius > 128) throw Error("--bloom: the radius must be 2..128 pixels");
  if (!(p.ssaoRadius >= 0.0f)) throw Error("--ssao: the radius must be >= 0 (0: automatic)");
  if (p.ssaoSamples < 1 || p.ssaoSamples > 256) throw Error("--ssao: the sample count must be 1..256");
}

}  // namespace rast
