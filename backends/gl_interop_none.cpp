// Builds without graphics interop (host backends, HIP for now): the viewer
// uploads the colour buffer through the host. For host backends that is no
// extra copy: the buffer is already in host memory.
#include "backends/gl_interop.h"

namespace rast {

const char* GlTextureInterop::name() { return "none"; }

std::unique_ptr<GlTextureInterop> GlTextureInterop::create(unsigned, std::string* why) {
  if (why) *why = "this build has no graphics interop";
  return nullptr;
}

GlTextureInterop::~GlTextureInterop() = default;

bool GlTextureInterop::copyFrom(const void*, int, int, std::string* why) {
  if (why) *why = "this build has no graphics interop";
  return false;
}

}  // namespace rast
