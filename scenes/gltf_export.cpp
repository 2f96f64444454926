// Writes a Scene as a binary glTF 2.0 file (tinygltf), so that the built-in
// stress scenes can be drawn by other renderers (glref, Blender, ...). Node
// order follows the draws, so primitive ids match rast's.
#include "scenes/gltf_export.h"

#include "scenes/gltf_export_motion.h"

#include "host/image/safe_output.h"
#include "scenes/gltf_export_material.h"

#include <tiny_gltf.h>

#include <stb/stb_image_write.h>

#include <cmath>
#include <cstring>
#include <sstream>

namespace rast {
namespace {

struct BinWriter {
  tinygltf::Model& m;
  std::vector<unsigned char>& bin;

  // Appends raw bytes as a buffer view (4-byte aligned); returns its index.
  int view(const void* data, size_t bytes, int target) {
    while (bin.size() % 4) bin.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = bin.size();
    v.byteLength = bytes;
    v.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + bytes);
    m.bufferViews.push_back(v);
    return int(m.bufferViews.size() - 1);
  }

  int accessor(const void* data, size_t count, int type, int comps, int target, bool minMax = false) {
    tinygltf::Accessor a;
    a.bufferView = view(data, count * comps * 4, target);
    a.componentType = type;
    a.count = count;
    a.type = comps == 1 ? TINYGLTF_TYPE_SCALAR : comps == 2 ? TINYGLTF_TYPE_VEC2 : comps == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
    if (minMax) {  // POSITION must carry its bounds (finite values only)
      const float* f = static_cast<const float*>(data);
      a.minValues.assign(comps, 0.0);
      a.maxValues.assign(comps, 0.0);
      bool first = true;
      for (size_t i = 0; i < count; ++i) {
        bool finite = true;
        for (int c = 0; c < comps; ++c) finite &= std::isfinite(f[i * comps + c]);
        if (!finite) continue;
        for (int c = 0; c < comps; ++c) {
          const double v = f[i * comps + c];
          a.minValues[c] = first ? v : std::min(a.minValues[c], v);
          a.maxValues[c] = first ? v : std::max(a.maxValues[c], v);
        }
        first = false;
      }
    }
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
  }
};

void appendBytes(void* ctx, void* data, int size) {
  auto* v = static_cast<std::vector<unsigned char>*>(ctx);
  const auto* p = static_cast<const unsigned char*>(data);
  v->insert(v->end(), p, p + size);
}

}  // namespace

void exportGlb(const Scene& s, const std::string& path) {
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "rast export";
  m.buffers.resize(1);
  std::vector<unsigned char>& bin = m.buffers[0].data;
  BinWriter w{m, bin};

  for (const Texture& t : s.textures) {
    std::vector<unsigned char> png;
    stbi_write_png_to_func(appendBytes, &png, t.width, t.height, 4, t.rgba.data(), t.width * 4);
    tinygltf::Image im;
    im.mimeType = "image/png";
    im.bufferView = w.view(png.data(), png.size(), 0);
    m.images.push_back(im);
    tinygltf::Sampler sm;
    sm.wrapS = t.wrapS;
    sm.wrapT = t.wrapT;
    m.samplers.push_back(sm);
    tinygltf::Texture tex;
    tex.source = int(m.images.size() - 1);
    tex.sampler = int(m.samplers.size() - 1);
    m.textures.push_back(tex);
  }
  for (const Material& mat : s.materials) {
    tinygltf::Material gm;
    gm.pbrMetallicRoughness.baseColorFactor = {mat.baseColorFactor.x, mat.baseColorFactor.y, mat.baseColorFactor.z,
                                               mat.baseColorFactor.w};
    gm.pbrMetallicRoughness.metallicFactor = 0.0;
    gm.pbrMetallicRoughness.roughnessFactor = 1.0;
    if (mat.texture >= 0) gm.pbrMetallicRoughness.baseColorTexture.index = mat.texture;
    gm.doubleSided = true;
    m.materials.push_back(gm);
  }
  for (const MeshPrim& p : s.prims) {
    tinygltf::Primitive gp;
    // A primitive has one kind: points, line segments (LINES) or triangles.
    const bool points = p.pointCount > 0, lines = p.lineCount > 0;
    gp.mode = points ? TINYGLTF_MODE_POINTS : lines ? TINYGLTF_MODE_LINE : TINYGLTF_MODE_TRIANGLES;
    gp.material = p.material;
    gp.attributes["POSITION"] = w.accessor(&s.positions[p.firstVertex], p.vertexCount, TINYGLTF_COMPONENT_TYPE_FLOAT, 3,
                                           TINYGLTF_TARGET_ARRAY_BUFFER, true);
    gp.attributes["NORMAL"] = w.accessor(&s.normals[p.firstVertex], p.vertexCount, TINYGLTF_COMPONENT_TYPE_FLOAT, 3,
                                         TINYGLTF_TARGET_ARRAY_BUFFER);
    if (!s.uvs.empty())
      gp.attributes["TEXCOORD_0"] = w.accessor(&s.uvs[p.firstVertex], p.vertexCount, TINYGLTF_COMPONENT_TYPE_FLOAT, 2,
                                               TINYGLTF_TARGET_ARRAY_BUFFER);
    if (!s.colors.empty())
      gp.attributes["COLOR_0"] = w.accessor(&s.colors[p.firstVertex], p.vertexCount, TINYGLTF_COMPONENT_TYPE_FLOAT, 4,
                                            TINYGLTF_TARGET_ARRAY_BUFFER);
    const uint32_t* idx = points  ? s.pointIndices.data() + p.firstPoint
                          : lines ? s.lineIndices.data() + size_t(p.firstLine) * 2
                                  : s.indices.data() + size_t(p.firstTri) * 3;
    const size_t n = points ? p.pointCount : lines ? size_t(p.lineCount) * 2 : size_t(p.triCount) * 3;
    gp.indices = w.accessor(idx, n, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(gp);
    m.meshes.push_back(mesh);
  }
  tinygltf::Scene scene;
  if (!writeMotion(s, m, scene))  // a scene that moves: its rig's nodes place the draws (gltf_export_motion.h)
  for (const Draw& d : s.draws) {
    tinygltf::Node n;
    n.mesh = int(d.prim);
    n.matrix.assign(&d.model[0][0], &d.model[0][0] + 16);
    m.nodes.push_back(n);
    scene.nodes.push_back(int(m.nodes.size() - 1));
  }
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  exportMaterialModel(s, m);  // materials, samplers, tangents, lights, cameras (gltf_export_material.h)
  tinygltf::TinyGLTF writer;
  // Encoded in memory, then written atomically (host/image/safe_output.h).
  std::ostringstream glb;
  if (!writer.WriteGltfSceneToStream(&m, glb, true, true)) throw Error("cannot encode '" + printable(path) + "'");
  const std::string bytes = glb.str();
  writeFileAtomically(path, bytes.data(), bytes.size());
}

}  // namespace rast
