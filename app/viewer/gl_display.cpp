#include "app/viewer/gl_display.h"

#include "backends/gl_interop.h"

#include <GL/gl.h>

#include <algorithm>
#include <cstdio>

namespace rast {

GlDisplay::GlDisplay() = default;

GlDisplay::~GlDisplay() {
  interop_.reset();  // unregisters from the GPU runtime before the texture goes
  if (tex_) glDeleteTextures(1, &tex_);
}

void GlDisplay::ensureTexture(int w, int h) {
  if (tex_ && texW_ == w && texH_ == h) return;
  interop_.reset();
  if (!tex_) glGenTextures(1, &tex_);
  glBindTexture(GL_TEXTURE_2D, tex_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  texW_ = w;
  texH_ = h;
}

void GlDisplay::uploadHost(const uint32_t* rgba, int w, int h, bool topDown, DisplayPath path) {
  ensureTexture(w, h);
  glBindTexture(GL_TEXTURE_2D, tex_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  // uint32 R-in-the-low-byte on a little-endian host is the byte order R,G,B,A.
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  topDown_ = topDown;
  path_ = path;
}

bool GlDisplay::uploadDevice(const void* deviceRgbaBottomUp, int w, int h) {
  if (interopFailed_ || !deviceRgbaBottomUp) return false;
  ensureTexture(w, h);
  std::string why;
  if (!interop_) {
    interop_ = GlTextureInterop::create(tex_, &why);
    if (!interop_) {
      interopFailed_ = true;
      fallbackReason_ = why;
      std::fprintf(stderr, "rast-viewer: graphics interop unavailable (%s); uploading through the host\n", why.c_str());
      return false;
    }
  }
  if (!interop_->copyFrom(deviceRgbaBottomUp, w, h, &why)) {
    interop_.reset();
    interopFailed_ = true;
    fallbackReason_ = why;
    std::fprintf(stderr, "rast-viewer: graphics interop failed (%s); uploading through the host\n", why.c_str());
    return false;
  }
  topDown_ = false;
  path_ = DisplayPath::Interop;
  return true;
}

std::string GlDisplay::pathDescription() const {
  switch (path_) {
    case DisplayPath::None: return "none yet";
    case DisplayPath::Interop: return std::string(GlTextureInterop::name()) + " (device to device)";
    case DisplayPath::HostDirect: return "host memory (the pipeline's buffer, no copy)";
    case DisplayPath::HostCopy:
      return "host copy (interop unavailable: " + (fallbackReason_.empty() ? std::string("--no-interop") : fallbackReason_) + ")";
  }
  return "?";
}

void GlDisplay::draw(int fbW, int fbH) {
  glViewport(0, 0, fbW, fbH);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (!tex_) return;
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_LIGHTING);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glEnable(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, tex_);
  // Pixel for pixel when the window and the image have the same size (the
  // usual case: the framebuffers follow the window), filtered otherwise.
  const GLint f = (fbW == texW_ && fbH == texH_) ? GL_NEAREST : GL_LINEAR;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, f);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, f);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  const float tTop = topDown_ ? 0.0f : 1.0f, tBottom = 1.0f - tTop;
  glColor4f(1, 1, 1, 1);
  glBegin(GL_QUADS);
  glTexCoord2f(0.0f, tBottom); glVertex2f(-1.0f, -1.0f);
  glTexCoord2f(1.0f, tBottom); glVertex2f(1.0f, -1.0f);
  glTexCoord2f(1.0f, tTop); glVertex2f(1.0f, 1.0f);
  glTexCoord2f(0.0f, tTop); glVertex2f(-1.0f, 1.0f);
  glEnd();
  glDisable(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, 0);
}

std::vector<uint32_t> GlDisplay::readWindow(int w, int h) {
  std::vector<uint32_t> bu(size_t(w) * h), td(bu.size());
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bu.data());
  for (int y = 0; y < h; ++y)
    std::copy(bu.begin() + size_t(h - 1 - y) * w, bu.begin() + size_t(h - y) * w, td.begin() + size_t(y) * w);
  for (uint32_t& p : td) p |= 0xff000000u;
  return td;
}

}  // namespace rast
