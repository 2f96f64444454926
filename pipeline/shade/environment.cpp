// Filtering an environment once on the device, as the Khronos Sample
// Renderer's iblSampler does it (docs/lighting.md): the panorama resampled to
// a cube map with a full box-filtered mip chain, then GGX importance sampling
// of that chain per specular level (each sample read at the mip level its pdf
// calls for, Krivanek and Colbert's filtered importance sampling), cosine
// sampling for the irradiance, and the split-sum table. The sample directions
// and levels of detail (trigonometry, log2) are computed once on the host and
// uploaded, so the kernels use only +, -, *, / and sqrt: the maps are the same
// bits on every backend.
#include "pipeline/shade/environment.h"

#include "base/error.h"
#include "pipeline/shade/cube_map.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace rast {
namespace {

int log2Exact(int v) {
  int l = 0;
  while ((1 << l) < v) ++l;
  return (1 << l) == v ? l : -1;
}

void needInt(const char* what, int v, int lo, int hi) {
  if (v < lo || v > hi)
    throw Error(std::string("environment option ") + what + " = " + std::to_string(v) + " is outside " +
                std::to_string(lo) + ".." + std::to_string(hi));
}

void checkOptions(const EnvOptions& o) {
  const int l = log2Exact(o.faceSize);
  if (l < 3 || l > 12)
    throw Error("environment option faceSize = " + std::to_string(o.faceSize) + " is not a power of two in 8..4096");
  needInt("lowestMipLevel", o.lowestMipLevel, 0, l - 1);
  needInt("mip count", l + 1 - o.lowestMipLevel, 2, kMaxEnvLevels);
  needInt("ggxSamples", o.ggxSamples, 1, 1 << 16);
  needInt("lambertSamples", o.lambertSamples, 1, 1 << 16);
  needInt("lutSamples", o.lutSamples, 1, 1 << 16);
  needInt("diffuseSize", o.diffuseSize, 1, 1024);
  needInt("lutSize", o.lutSize, 2, 4096);
  if (!std::isfinite(o.intensity) || o.intensity < 0.0f)
    throw Error("environment intensity " + std::to_string(o.intensity) + " is not a finite number >= 0");
  if (!std::isfinite(o.rotationDegrees)) throw Error("environment rotation is not a finite number of degrees");
  if (!(o.backgroundBlur >= 0.0f && o.backgroundBlur <= 1.0f))
    throw Error("environment background blur " + std::to_string(o.backgroundBlur) + " is outside 0..1");
}

// Van der Corput's radical inverse in base 2 (the second Hammersley coordinate).
double radicalInverse(uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return double(bits) * 2.3283064365386963e-10;
}

constexpr double kPi = 3.14159265358979323846;

// The reference's lod of a sample of density pdf: the mip level whose texels
// subtend the sample's share of the sphere, 0.5 log2(6 w^2 / (N pdf)).
float sampleLod(double pdf, int width, int count) {
  return float(0.5 * std::log2(6.0 * double(width) * double(width) / (double(count) * pdf)));
}

// GGX samples of one roughness around +Z, reflected about the view = normal:
// (L.x, L.y, L.z, N.L) and the lod, for samples with N.L > 0 (the others add
// nothing, as in the reference).
void ggxTable(double roughness, const EnvOptions& o, std::vector<float4>& dirs, std::vector<float>& lods) {
  const double alpha = roughness * roughness;
  for (int i = 0; i < o.ggxSamples; ++i) {
    const double xx = double(i) / o.ggxSamples, xy = radicalInverse(uint32_t(i));
    double c = std::sqrt((1.0 - xy) / (1.0 + (alpha * alpha - 1.0) * xy));
    c = c > 1.0 ? 1.0 : c;
    const double s = std::sqrt(1.0 - c * c), phi = 2.0 * kPi * xx;
    // D_GGX as the reference writes it, with its alpha = roughness^2.
    const double a = c * alpha, k = alpha / (1.0 - c * c + a * a);
    const double pdf = k * k / kPi / 4.0;
    const double hx = s * std::cos(phi), hy = s * std::sin(phi), hz = c;
    const double lx = 2.0 * hz * hx, ly = 2.0 * hz * hy, lz = 2.0 * hz * hz - 1.0;  // reflect(-N, H), N = +Z
    if (!(lz > 0.0)) continue;
    dirs.push_back({float(lx), float(ly), float(lz), float(lz)});
    lods.push_back(roughness == 0.0 ? 0.0f : sampleLod(pdf, o.faceSize, o.ggxSamples));
  }
}

// Cosine-weighted samples around +Z and their lods.
std::vector<float4> lambertTable(const EnvOptions& o) {
  std::vector<float4> t;
  for (int i = 0; i < o.lambertSamples; ++i) {
    const double xx = double(i) / o.lambertSamples, xy = radicalInverse(uint32_t(i));
    const double c = std::sqrt(1.0 - xy), s = std::sqrt(xy), phi = 2.0 * kPi * xx;
    t.push_back({float(s * std::cos(phi)), float(s * std::sin(phi)), float(c),
                 sampleLod(c / kPi, o.faceSize, o.lambertSamples)});
  }
  return t;
}

template <class T>
DView<T> upload(const char* label, const std::vector<T>& v) {
  DView<T> d = allocUninit<T>(label, v.size() ? v.size() : 1);
  if (!v.empty()) {
    Kokkos::View<const T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(), v.size());
    Kokkos::deep_copy(Kokkos::subview(d, std::make_pair(size_t(0), v.size())), h);
  }
  return d;
}

struct Chain {
  uint32_t offset[kMaxEnvLevels + 12];
  int32_t size, levels;
};

// A frame (tangent, bitangent, normal) around n as the reference's generateTBN builds it.
KOKKOS_INLINE_FUNCTION void tangentFrame(float3 n, float3& t, float3& b) {
  b = {0.0f, 1.0f, 0.0f};
  const float up = n.y;
  if (1.0f - (up < 0.0f ? -up : up) <= 1e-7f) b = {0.0f, 0.0f, up > 0.0f ? 1.0f : -1.0f};
  t = normalize(cross(b, n));
  b = cross(n, t);
}

// Bilinear sample of a level's inner texels only (clamped at the face's edge):
// what the border texels are made from.
KOKKOS_INLINE_FUNCTION float4 innerBilinear(const DView<float4>& tex, uint32_t off, int32_t size, CubeCoord c) {
  const float hi = float(size - 1);
  float fx = c.s * float(size) - 0.5f, fy = c.t * float(size) - 0.5f;
  fx = fx >= 0.0f ? (fx <= hi ? fx : hi) : 0.0f;
  fy = fy >= 0.0f ? (fy <= hi ? fy : hi) : 0.0f;
  const int32_t x0 = int32_t(floorTexel(fx)), y0 = int32_t(floorTexel(fy));
  const int32_t x1 = imin(x0 + 1, size - 1), y1 = imin(y0 + 1, size - 1);
  const float a = fx - float(x0), b = fy - float(y0);
  const float4 t00 = tex(cubeTexelIndex(off, size, c.face, x0, y0)), t10 = tex(cubeTexelIndex(off, size, c.face, x1, y0));
  const float4 t01 = tex(cubeTexelIndex(off, size, c.face, x0, y1)), t11 = tex(cubeTexelIndex(off, size, c.face, x1, y1));
  return lerp4(lerp4(t00, t10, a), lerp4(t01, t11, a), b);
}

// Fills the one-texel border of every face of a level from the neighbouring
// faces' texels, sampled along the border texel's own direction.
void fillBorders(const DView<float4>& tex, uint32_t off, int32_t size) {
  const int32_t perFace = 4 * (size + 1);
  Kokkos::parallel_for("rast::shade::ibl::borders", Range(0, 6 * perFace), KOKKOS_LAMBDA(const int64_t i) {
    const int32_t face = int32_t(i / perFace), b = int32_t(i % perFace);
    int32_t x, y;
    if (b < size + 2) {
      x = b - 1, y = -1;
    } else if (b < 2 * (size + 2)) {
      x = b - (size + 2) - 1, y = size;
    } else if (b < 2 * (size + 2) + size) {
      x = -1, y = b - 2 * (size + 2);
    } else {
      x = size, y = b - 2 * (size + 2) - size;
    }
    const CubeCoord c = cubeCoord(cubeTexelDir(face, x, y, size));
    tex(cubeTexelIndex(off, size, face, x, y)) = innerBilinear(tex, off, size, c);
  });
}

}  // namespace

EnvOptions neutralOptions() {
  EnvOptions o;
  o.faceSize = 64;
  o.lowestMipLevel = 2;
  o.diffuseSize = 16;
  o.lutSize = 128;
  return o;
}

uint64_t EnvironmentGPU::bytes() const { return viewBytes(specular) + viewBytes(diffuse) + viewBytes(lut); }

uint64_t environmentBytes(const EnvOptions& o) {
  checkOptions(o);
  const int mips = log2Exact(o.faceSize) + 1 - o.lowestMipLevel;
  uint64_t texels = 0;
  for (int l = 0; l < mips; ++l) texels += cubeLevelTexels(o.faceSize >> l);
  texels += cubeLevelTexels(o.diffuseSize);
  return texels * sizeof(float4) + uint64_t(o.lutSize) * uint64_t(o.lutSize) * sizeof(float2);
}

uint64_t environmentBuildBytes(const EnvOptions& o, int w, int h) {
  checkOptions(o);
  uint64_t texels = 0;
  for (int s = o.faceSize; s >= 1; s /= 2) texels += cubeLevelTexels(s);
  const uint64_t tables = uint64_t(o.ggxSamples) * kMaxEnvLevels * (sizeof(float4) + sizeof(float)) +
                          uint64_t(o.lambertSamples + o.lutSamples) * sizeof(float4);
  return mulSat(mulSat(uint64_t(w), uint64_t(h)), 3 * sizeof(float)) + texels * sizeof(float4) + tables;
}

EnvViewRays envViewRays(const mat4d& vp, int width, int height) {
  // The inverse by Gauss-Jordan elimination with partial pivoting, in double
  // (a[row][col] of the column-major m).
  double a[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      a[r][c] = vp.m[c * 4 + r];
      a[r][4 + c] = r == c ? 1.0 : 0.0;
    }
  for (int c = 0; c < 4; ++c) {
    int piv = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[piv][c])) piv = r;
    if (!(std::fabs(a[piv][c]) > 1e-300)) return {{0, 0, -1}, {0, 0, 0}, {0, 0, 0}};  // singular: any ray
    for (int k = 0; k < 8; ++k) std::swap(a[c][k], a[piv][k]);
    const double d = a[c][c];
    for (int k = 0; k < 8; ++k) a[c][k] /= d;
    for (int r = 0; r < 4; ++r)
      if (r != c) {
        const double f = a[r][c];
        for (int k = 0; k < 8; ++k) a[r][k] -= f * a[c][k];
      }
  }
  // The world-space ray through NDC (x, y): unproject at depths +-0.5.
  auto ray = [&](double x, double y, double r[3]) {
    double p[2][3];
    for (int k = 0; k < 2; ++k) {
      const double z = k ? 0.5 : -0.5, c[4] = {x, y, z, 1.0};
      double q[4];
      for (int row = 0; row < 4; ++row)
        q[row] = a[row][4] * c[0] + a[row][5] * c[1] + a[row][6] * c[2] + a[row][7] * c[3];
      for (int i = 0; i < 3; ++i) p[k][i] = q[i] / q[3];
    }
    for (int i = 0; i < 3; ++i) r[i] = p[1][i] - p[0][i];
  };
  // Pixel (px, py) from the top has NDC (2 (px + 0.5) / w - 1, 1 - 2 (py + 0.5) / h).
  double r0[3], rx[3], ry[3];
  ray(1.0 / width - 1.0, 1.0 - 1.0 / height, r0);
  ray(3.0 / width - 1.0, 1.0 - 1.0 / height, rx);
  ray(1.0 / width - 1.0, 1.0 - 3.0 / height, ry);
  EnvViewRays out;
  out.d00 = {float(r0[0]), float(r0[1]), float(r0[2])};
  out.dx = {float(rx[0] - r0[0]), float(rx[1] - r0[1]), float(rx[2] - r0[2])};
  out.dy = {float(ry[0] - r0[0]), float(ry[1] - r0[1]), float(ry[2] - r0[2])};
  return out;
}

void setEnvironmentLook(EnvironmentGPU& env, const EnvOptions& o) {
  checkOptions(o);
  const double r = double(o.rotationDegrees) / 180.0 * kPi;
  env.cosRot = float(std::cos(r));
  env.sinRot = float(std::sin(r));
  env.intensity = o.intensity;
  env.backgroundLod = o.backgroundBlur * float(env.mipCount - 1);
}

EnvironmentGPU loadEnvironment(const std::string& path, const EnvOptions& o, MemoryLedger& ledger) {
  if (!path.empty()) {
    const HdrImage img = readHdr(path, ledger);
    EnvironmentGPU env = buildEnvironment(img, o, ledger);
    ledger.release(img.bytes());  // the host panorama goes when this returns
    return env;
  }
  EnvOptions n = neutralOptions();
  n.intensity = o.intensity;
  n.rotationDegrees = o.rotationDegrees;
  n.backgroundBlur = o.backgroundBlur;
  return buildEnvironment(neutralEnvironment(), n, ledger);
}

EnvironmentGPU buildEnvironment(const HdrImage& img, const EnvOptions& o, MemoryLedger& ledger) {
  checkOptions(o);
  if (img.width < 1 || img.height < 1 || img.rgb.size() != size_t(img.width) * size_t(img.height) * 3)
    throw Error("environment '" + printable(img.name) + "' has no pixels");
  const uint64_t held = environmentBytes(o);
  const std::string what = "the filtered environment '" + printable(img.name) + "'";
  ledger.check(what + " while filtering", addSat(held, environmentBuildBytes(o, img.width, img.height)));
  ledger.charge(what, held);

  // The panorama's cube map with every level down to 1x1 (the reference's
  // generateMipmap): the filters read it at the lod of each sample.
  Chain src{};
  src.size = o.faceSize;
  src.levels = log2Exact(o.faceSize) + 1;
  uint32_t total = 0;
  for (int l = 0; l < src.levels; ++l) {
    src.offset[l] = total;
    total += cubeLevelTexels(o.faceSize >> l);
  }
  DView<float4> cube = allocUninit<float4>("ibl.source_cube", total);
  {
    DView<float> pano = upload("ibl.panorama", img.rgb);
    const int32_t W = img.width, H = img.height, s = o.faceSize;
    Kokkos::parallel_for("rast::shade::ibl::panorama_to_cube", Range(0, int64_t(6) * s * s),
                         KOKKOS_LAMBDA(const int64_t i) {
      const int32_t face = int32_t(i / (int64_t(s) * s)), r = int32_t(i % (int64_t(s) * s));
      const int32_t x = r % s, y = r / s;
      const float2 uv = panoramaUV(normalize(cubeTexelDir(face, x, y, s)));
      // Bilinear, edges clamped (the reference's MIRRORED_REPEAT reads the
      // same texels within half a texel of the edge).
      const float fx = uv.x * float(W) - 0.5f, fy = uv.y * float(H) - 0.5f;
      const float flx = floorTexel(fx), fly = floorTexel(fy);
      const float a = fx - flx, b = fy - fly;
      const int32_t x0 = imin(imax(int32_t(flx), 0), W - 1), x1 = imin(imax(int32_t(flx) + 1, 0), W - 1);
      const int32_t y0 = imin(imax(int32_t(fly), 0), H - 1), y1 = imin(imax(int32_t(fly) + 1, 0), H - 1);
      float rgb[3];
      for (int c = 0; c < 3; ++c) {
        const float t00 = pano((int64_t(y0) * W + x0) * 3 + c), t10 = pano((int64_t(y0) * W + x1) * 3 + c);
        const float t01 = pano((int64_t(y1) * W + x0) * 3 + c), t11 = pano((int64_t(y1) * W + x1) * 3 + c);
        rgb[c] = (t00 * (1.0f - a) + t10 * a) * (1.0f - b) + (t01 * (1.0f - a) + t11 * a) * b;
      }
      cube(cubeTexelIndex(0u, s, face, x, y)) = {rgb[0], rgb[1], rgb[2], 1.0f};
    });
  }
  fillBorders(cube, 0u, o.faceSize);
  for (int l = 1; l < src.levels; ++l) {
    const int32_t s = o.faceSize >> l;
    const uint32_t off = src.offset[l], offUp = src.offset[l - 1];
    Kokkos::parallel_for("rast::shade::ibl::downsample", Range(0, int64_t(6) * s * s), KOKKOS_LAMBDA(const int64_t i) {
      const int32_t face = int32_t(i / (int64_t(s) * s)), r = int32_t(i % (int64_t(s) * s));
      const int32_t x = r % s, y = r / s;
      const float4 a = cube(cubeTexelIndex(offUp, 2 * s, face, 2 * x, 2 * y));
      const float4 b = cube(cubeTexelIndex(offUp, 2 * s, face, 2 * x + 1, 2 * y));
      const float4 c = cube(cubeTexelIndex(offUp, 2 * s, face, 2 * x, 2 * y + 1));
      const float4 d = cube(cubeTexelIndex(offUp, 2 * s, face, 2 * x + 1, 2 * y + 1));
      cube(cubeTexelIndex(off, s, face, x, y)) = ((a + b) + (c + d)) * 0.25f;
    });
    fillBorders(cube, off, s);
  }

  EnvironmentGPU env;
  env.faceSize = o.faceSize;
  env.mipCount = src.levels - o.lowestMipLevel;
  env.diffuseSize = o.diffuseSize;
  env.lutSize = o.lutSize;
  uint32_t specTotal = 0;
  for (int l = 0; l < env.mipCount; ++l) {
    env.levelOffset[l] = specTotal;
    specTotal += cubeLevelTexels(o.faceSize >> l);
  }
  env.specular = allocUninit<float4>("ibl.specular", specTotal);
  env.diffuse = allocUninit<float4>("ibl.diffuse", cubeLevelTexels(o.diffuseSize));
  env.lut = allocUninit<float2>("ibl.brdf_lut", size_t(o.lutSize) * size_t(o.lutSize));
  setEnvironmentLook(env, o);

  // Specular: level 0 is roughness 0, the panorama's cube itself (every GGX
  // sample is the normal, read at lod 0); level l is roughness l / (mips - 1).
  std::vector<float4> dirs;
  std::vector<float> lods;
  std::vector<uint32_t> first{0};
  for (int l = 1; l < env.mipCount; ++l) {
    ggxTable(double(l) / double(env.mipCount - 1), o, dirs, lods);
    first.push_back(uint32_t(dirs.size()));
  }
  const DView<float4> gDirs = upload("ibl.ggx_dirs", dirs);
  const DView<float> gLods = upload("ibl.ggx_lods", lods);
  const DView<float4> spec = env.specular;
  {
    const uint32_t n0 = cubeLevelTexels(o.faceSize);
    Kokkos::parallel_for("rast::shade::ibl::prefilter_specular", Range(0, int64_t(n0)),
                         KOKKOS_LAMBDA(const int64_t i) { spec(i) = cube(i); });
  }
  for (int l = 1; l < env.mipCount; ++l) {
    const int32_t s = o.faceSize >> l;
    const uint32_t off = env.levelOffset[l], k0 = first[l - 1], k1 = first[l];
    Kokkos::parallel_for("rast::shade::ibl::prefilter_specular", Range(0, int64_t(6) * s * s),
                         KOKKOS_LAMBDA(const int64_t i) {
      const int32_t face = int32_t(i / (int64_t(s) * s)), r = int32_t(i % (int64_t(s) * s));
      const int32_t x = r % s, y = r / s;
      const float3 n = normalize(cubeTexelDir(face, x, y, s));
      float3 t, b;
      tangentFrame(n, t, b);
      float4 sum = {0.0f, 0.0f, 0.0f, 0.0f};
      float weight = 0.0f;
      for (uint32_t k = k0; k < k1; ++k) {
        const float4 d = gDirs(k);
        // Unit up to rounding, and a cube lookup needs no unit vector.
        const float3 L = t * d.x + b * d.y + n * d.z;
        sum = sum + cubeTrilinear(cube, src.offset, src.size, src.levels, L, gLods(k)) * d.w;
        weight += d.w;
      }
      const float inv = weight > 0.0f ? 1.0f / weight : 0.0f;
      spec(cubeTexelIndex(off, s, face, x, y)) = {sum.x * inv, sum.y * inv, sum.z * inv, 1.0f};
    });
    fillBorders(spec, off, s);
  }

  // Irradiance / pi: the mean of cosine-distributed samples.
  {
    const DView<float4> lam = upload("ibl.lambert_dirs", lambertTable(o));
    const DView<float4> diff = env.diffuse;
    const int32_t s = o.diffuseSize, count = o.lambertSamples;
    Kokkos::parallel_for("rast::shade::ibl::irradiance", Range(0, int64_t(6) * s * s), KOKKOS_LAMBDA(const int64_t i) {
      const int32_t face = int32_t(i / (int64_t(s) * s)), r = int32_t(i % (int64_t(s) * s));
      const int32_t x = r % s, y = r / s;
      const float3 n = normalize(cubeTexelDir(face, x, y, s));
      float3 t, b;
      tangentFrame(n, t, b);
      float4 sum = {0.0f, 0.0f, 0.0f, 0.0f};
      for (int32_t k = 0; k < count; ++k) {
        const float4 d = lam(k);
        sum = sum + cubeTrilinear(cube, src.offset, src.size, src.levels, t * d.x + b * d.y + n * d.z, d.w);
      }
      const float inv = 1.0f / float(count);
      diff(cubeTexelIndex(0u, s, face, x, y)) = {sum.x * inv, sum.y * inv, sum.z * inv, 1.0f};
    });
    fillBorders(diff, 0u, s);
  }

  // The split-sum table: row j is roughness (j + 0.5) / n, column i is
  // NdotV (i + 0.5) / n (texel centres, as the reference renders it).
  {
    std::vector<float4> seq;
    for (int k = 0; k < o.lutSamples; ++k) {
      const double phi = 2.0 * kPi * double(k) / o.lutSamples;
      seq.push_back({float(std::cos(phi)), float(std::sin(phi)), float(radicalInverse(uint32_t(k))), 0.0f});
    }
    const DView<float4> q = upload("ibl.lut_sequence", seq);
    const DView<float2> lut = env.lut;
    const int32_t n = o.lutSize, count = o.lutSamples;
    Kokkos::parallel_for("rast::shade::ibl::brdf_lut", Range(0, int64_t(n) * n), KOKKOS_LAMBDA(const int64_t i) {
      const float ndv = (float(i % n) + 0.5f) / float(n), rough = (float(i / n) + 0.5f) / float(n);
      const float alpha = rough * rough, a2 = alpha * alpha;
      const float3 V = {::sqrtf(1.0f - ndv * ndv), 0.0f, ndv};
      float A = 0.0f, B = 0.0f;
      for (int32_t k = 0; k < count; ++k) {
        const float4 e = q(k);
        float c = ::sqrtf((1.0f - e.z) / (1.0f + (a2 - 1.0f) * e.z));
        c = c < 1.0f ? c : 1.0f;
        const float sn = ::sqrtf(1.0f - c * c);
        const float3 H = normalize(make3(sn * e.x, sn * e.y, c));
        const float vdh = dot(V, H);
        const float3 L = normalize(H * (2.0f * vdh) - V);
        const float ndl = clamp01(L.z), ndh = clamp01(H.z), vh = clamp01(vdh);
        if (ndl > 0.0f) {
          const float gv = ndl * ::sqrtf(ndv * ndv * (1.0f - a2) + a2);
          const float gl = ndv * ::sqrtf(ndl * ndl * (1.0f - a2) + a2);
          const float vpdf = 0.5f / (gv + gl) * vh * ndl / ndh;
          const float m = 1.0f - vh, m2 = m * m, fc = m2 * m2 * m;
          A += (1.0f - fc) * vpdf;
          B += fc * vpdf;
        }
      }
      lut(i) = {4.0f * A / float(count), 4.0f * B / float(count)};
    });
  }
  Kokkos::fence();
  return env;
}

}  // namespace rast
