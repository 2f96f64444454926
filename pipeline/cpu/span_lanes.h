// The CPU span kernel's members that shade a set of pixels as the lanes of
// vectors, declared in ShadeSpans (shade_spans.h, which includes this header
// after the struct): a span of one triangle along a row (span) or any pixels
// of one triangle given by their coordinates (shadeLanes), short runs of
// different triangles batched lane by lane (addLanes, shadeBatch: LaneBatch,
// lane_batch.h), and what both add to the span arithmetic of span_math.h: the
// scene's lights (addLights) and the texture (texture: span_texture.h, or per
// pixel where it does not apply).
//
// They are the kernel's half that turns pixels into colours, apart from the
// half in shade_spans.h that decides which pixels go together. They are
// defined out of the struct, in the order they were declared, so that each
// header stays readable; they are the same inline members as before.
#pragma once

#include "pipeline/cpu/lane_batch.h"
#include "pipeline/cpu/shade_spans.h"
#include "pipeline/cpu/span_math.h"
#include "pipeline/cpu/span_texture.h"

namespace rast {
namespace shading {

// The scene's directional lights (without the headlight) added to the
// diffuse terms of mb lanes, given their normals.
KOKKOS_INLINE_FUNCTION void ShadeSpans::addLights(int32_t mb, const float* nx, const float* ny, const float* nz,
                                                  float* diffuse) const {
  if (p.headlight) return;
  const int nl = int(lights.extent(0));
  for (int l = 0; l < nl; ++l) {
    const float3 L = lights(l).direction;
    const float I = lights(l).intensity;
    for (int32_t j = 0; j < mb; ++j) {
      const float ndl = nx[j] * L.x + ny[j] * L.y + nz[j] * L.z;
      diffuse[j] += I * (ndl > 0.0f ? ndl : 0.0f);
    }
  }
}

// Pixels [xa, xa + len) of row Y, of triangle f, as lanes of the batch.
KOKKOS_INLINE_FUNCTION void ShadeSpans::addLanes(LaneBatch& L, const TriFrag& f, int32_t xa, int32_t Y,
                                                int32_t len) const {
  const bool persp = p.perspective != 0;
  for (int32_t i = 0; i < len; ++i) {
    const int32_t j = L.m++;
    const int32_t X = xa + i;
    L.X[j] = X;
    L.e0[j] = float(double(f.e.eval(0, X, Y)));  // as span(): exact in double, then rounded once
    L.e1[j] = float(double(f.e.eval(1, X, Y)));
    L.e2[j] = float(double(f.e.eval(2, X, Y)));
    L.ia[j] = f.invArea;
    L.iw0[j] = persp ? f.invW[0] : 1.0f;
    L.iw1[j] = persp ? f.invW[1] : 1.0f;
    L.iw2[j] = persp ? f.invW[2] : 1.0f;
    L.t00[j] = f.corner[0][0]; L.t10[j] = f.corner[1][0]; L.t20[j] = f.corner[2][0];
    L.t01[j] = f.corner[0][1]; L.t11[j] = f.corner[1][1]; L.t21[j] = f.corner[2][1];
    for (int c = 0; c < 3; ++c) {
      L.n[3 * c][j] = f.n[c].x; L.n[3 * c + 1][j] = f.n[c].y; L.n[3 * c + 2][j] = f.n[c].z;
      L.q[3 * c][j] = f.pos[c].x; L.q[3 * c + 1][j] = f.pos[c].y; L.q[3 * c + 2][j] = f.pos[c].z;
    }
    L.base[0][j] = f.baseColor.x; L.base[1][j] = f.baseColor.y; L.base[2][j] = f.baseColor.z; L.base[3][j] = f.baseColor.w;
    if (hasColor)
      for (int c = 0; c < 3; ++c) {
        L.col[4 * c][j] = f.col[c].x; L.col[4 * c + 1][j] = f.col[c].y;
        L.col[4 * c + 2][j] = f.col[c].z; L.col[4 * c + 3][j] = f.col[c].w;
      }
  }
}

// The batch's pixels of row Y (rowStart: its first pixel's index): as
// shadeLanes, each lane with its own triangle's constants.
KOKKOS_INLINE_FUNCTION void ShadeSpans::shadeBatch(LaneBatch& L, int64_t rowStart, int32_t Y) const {  // empties it
  const int32_t m = L.m;
  const bool wide = m >= kSpanWideMin;
  const int32_t mb = wide ? spanBlocks(m) : m;
  for (int32_t i = m; i < mb; ++i) {  // the last block's spare lanes: lane 0's triangle and pixel
    L.X[i] = L.X[0];
    L.e0[i] = L.e0[0]; L.e1[i] = L.e1[0]; L.e2[i] = L.e2[0];
    L.ia[i] = L.ia[0]; L.iw0[i] = L.iw0[0]; L.iw1[i] = L.iw1[0]; L.iw2[i] = L.iw2[0];
    L.t00[i] = L.t00[0]; L.t10[i] = L.t10[0]; L.t20[i] = L.t20[0];
    L.t01[i] = L.t01[0]; L.t11[i] = L.t11[0]; L.t21[i] = L.t21[0];
    for (int c = 0; c < 9; ++c) {
      L.n[c][i] = L.n[c][0];
      L.q[c][i] = L.q[c][0];
    }
    for (int c = 0; c < 4; ++c) L.base[c][i] = L.base[c][0];
    if (hasColor)
      for (int c = 0; c < 12; ++c) L.col[c][i] = L.col[c][0];
  }
  float b0[kMaxSpanRun], b1[kMaxSpanRun], b2[kMaxSpanRun];
  float nx[kMaxSpanRun], ny[kMaxSpanRun], nz[kMaxSpanRun];
  float diffuse[kMaxSpanRun];
  const float3 eye = p.frame(0).camera.eye;
  const float headI = p.headlight ? 1.0f - p.ambient : 0.0f;
  if (wide) laneLightingWide(L, mb, eye, p.ambient, headI, b0, b1, b2, nx, ny, nz, diffuse);
  else laneLighting(L, mb, eye, p.ambient, headI, b0, b1, b2, nx, ny, nz, diffuse);
  addLights(mb, nx, ny, nz, diffuse);
  float br[kMaxSpanRun], bg[kMaxSpanRun], bb[kMaxSpanRun], ba[kMaxSpanRun];
  for (int32_t j = 0; j < mb; ++j) {
    br[j] = L.base[0][j];
    bg[j] = L.base[1][j];
    bb[j] = L.base[2][j];
    ba[j] = L.base[3][j];
  }
  if (hasColor)
    for (int32_t j = 0; j < mb; ++j) {  // as shadeLanes, with each lane's corner colours
      br[j] = br[j] * (L.col[0][j] * b0[j] + L.col[4][j] * b1[j] + L.col[8][j] * b2[j]);
      bg[j] = bg[j] * (L.col[1][j] * b0[j] + L.col[5][j] * b1[j] + L.col[9][j] * b2[j]);
      bb[j] = bb[j] * (L.col[2][j] * b0[j] + L.col[6][j] * b1[j] + L.col[10][j] * b2[j]);
      ba[j] = ba[j] * (L.col[3][j] * b0[j] + L.col[7][j] * b1[j] + L.col[11][j] * b2[j]);
    }
  if (!p.floatOut) {
    uint32_t px[kMaxSpanRun];
    if (wide) packSpanWide(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), px);
    else packSpan(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), px);
    for (int32_t j = 0; j < m; ++j) color(rowStart + L.X[j]) = px[j];
    L.m = 0;
    return;
  }
  for (int32_t j = 0; j < m; ++j) {
    const float d = diffuse[j];
    hdr(rowStart + L.X[j]) = float4{br[j] * d + 0.0f, bg[j] * d + 0.0f, bb[j] * d + 0.0f, ba[j]};
  }
  L.m = 0;
}

// Pixels [xa, xa + m) of row Y, all of st's triangle (a raster triangle).
KOKKOS_INLINE_FUNCTION void ShadeSpans::span(SpanTri& st, int64_t out, int32_t xa, int32_t Y, int32_t m) const {
  const Edges& e = st.f.e;
  SpanConsts& k = st.k;
  k.s1 = double(e.eval(1, xa, Y));
  k.s2 = double(e.eval(2, xa, Y));
  k.s0 = double(e.eval(0, xa, Y));
  shadeLanes(st, m, out, nullptr, nullptr);
}

// m pixels of st's triangle: a row span from pixel `out` on (X null), or
// any pixels, given by their coordinates (X, Y; whole blocks of them).
KOKKOS_INLINE_FUNCTION void ShadeSpans::shadeLanes(SpanTri& st, int32_t m, int64_t out, const int32_t* X,
                                                   const int32_t* Y) const {
  const TriFrag& f = st.f;
  float b0[kMaxSpanRun], b1[kMaxSpanRun], b2[kMaxSpanRun];
  float nx[kMaxSpanRun], ny[kMaxSpanRun], nz[kMaxSpanRun];
  float diffuse[kMaxSpanRun];
  float br[kMaxSpanRun], bg[kMaxSpanRun], bb[kMaxSpanRun], ba[kMaxSpanRun];  // base colour
  // Screen-space weights from the exact edge values (as Shade::bary: l0 from
  // edge 1, l1 from edge 2, l2 from edge 0), then the perspective-correct
  // weights in the drawn triangle, the normal, the position and the
  // headlight of every pixel (Shade::bary, shadeFragment): spanLighting.
  const SpanConsts& k = st.k;
  // Lanes computed: a long span's loops (AVX-512 and AVX2 clones) run over whole blocks;
  // a short one's inline loops over its pixels only (one pixel each on
  // scenes of tiny triangles).
  const bool wide = m >= kSpanWideMin;
  const int32_t mb = wide ? spanBlocks(m) : m;
  if (X) {
    if (wide) spanLightingLanesWide(k, mb, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
    else spanLightingLanes(k, mb, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
  } else {
    if (wide) spanLightingWide(k, mb, b0, b1, b2, nx, ny, nz, diffuse);
    else spanLighting(k, mb, b0, b1, b2, nx, ny, nz, diffuse);
  }
  addLights(mb, nx, ny, nz, diffuse);
  // Base colour: material, texture, vertex colour.
  const float4 bc = f.baseColor;
  for (int32_t j = 0; j < mb; ++j) {
    br[j] = bc.x;
    bg[j] = bc.y;
    bb[j] = bc.z;
    ba[j] = bc.w;
  }
  if (f.textured) texture(st, m, mb, b0, b1, b2, br, bg, bb, ba);
  if (hasColor) {
    const float4 c0 = f.col[0], c1 = f.col[1], c2 = f.col[2];
    for (int32_t j = 0; j < mb; ++j) {
      // base * (col0 b0 + col1 b1 + col2 b2), per channel
      br[j] = br[j] * (c0.x * b0[j] + c1.x * b1[j] + c2.x * b2[j]);
      bg[j] = bg[j] * (c0.y * b0[j] + c1.y * b1[j] + c2.y * b2[j]);
      bb[j] = bb[j] * (c0.z * b0[j] + c1.z * b1[j] + c2.z * b2[j]);
      ba[j] = ba[j] * (c0.w * b0[j] + c1.w * b1[j] + c2.w * b2[j]);
    }
  }
  if (!p.floatOut) {
    uint32_t px[kMaxSpanRun];
    uint32_t* dst = X ? px : color.data() + out;
    // The host backends share host memory with their kernels: a plain pointer.
    if (wide) packSpanWide(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), dst);
    else packSpan(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), dst);
    if (X)
      for (int32_t j = 0; j < m; ++j) color(int64_t(Y[j]) * width + X[j]) = px[j];
    return;
  }
  for (int32_t j = 0; j < m; ++j) {
    const float d = diffuse[j];
    // rgb * diffuse + spec (0 in Lambert), as shadeFragment adds it
    hdr(X ? int64_t(Y[j]) * width + X[j] : out + j) = float4{br[j] * d + 0.0f, bg[j] * d + 0.0f, bb[j] * d + 0.0f, ba[j]};
  }
}

// The base colour times the texture at each pixel of the span (weights b0..b2).
// m pixels, mb lanes (as in span()).
KOKKOS_INLINE_FUNCTION void ShadeSpans::texture(const SpanTri& st, int32_t m, int32_t mb, const float* b0,
                                                const float* b1, const float* b2, float* br, float* bg, float* bb,
                                                float* ba) const {
  const TriFrag& f = st.f;
  if (p.filter != TexFilter::Nearest && st.tex.indexable) {
    int32_t i00[kMaxSpanRun], i10[kMaxSpanRun], i01[kMaxSpanRun], i11[kMaxSpanRun];
    float fa[kMaxSpanRun], fb[kMaxSpanRun];
    const bool wide = m >= kSpanWideMin;
    const SpanTex& x = st.tex;
    const int32_t bad = wide ? bilinearSetupWide(x, mb, b0, b1, b2, i00, i10, i01, i11, fa, fb)
                             : bilinearSetup(x, mb, b0, b1, b2, i00, i10, i01, i11, fa, fb);
    if (!bad) {
      if (wide) bilinearBlendWide(x.texels, x.lut, mb, i00, i10, i01, i11, fa, fb, br, bg, bb, ba);
      else bilinearBlend(x.texels, x.lut, mb, i00, i10, i01, i11, fa, fb, br, bg, bb, ba);
      return;
    }
  }
  for (int32_t j = 0; j < m; ++j) {
    const float2 uv = uvAt(f, b0[j], b1[j], b2[j]);
    const float4 tc = p.filter == TexFilter::Nearest ? sampleNearest(f.tex, texels, lut, uv.x, uv.y)
                                                     : sampleBilinear(f.tex, texels, lut, uv.x, uv.y);
    br[j] = br[j] * tc.x;
    bg[j] = bg[j] * tc.y;
    bb[j] = bb[j] * tc.z;
    ba[j] = ba[j] * tc.w;
  }
}

}  // namespace shading
}  // namespace rast
