#include "host/scene/camera_list.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rast {
namespace {

using nlohmann::json;

struct Where {
  const std::string& file;
  size_t view;
  std::string at(const std::string& key) const {
    return "--cameras " + printable(file) + ": view " + std::to_string(view) + (key.empty() ? "" : ", '" + key + "'");
  }
};

double number(const json& v, const Where& w, const std::string& key) {
  if (!v.is_number()) throw Error(w.at(key) + ": expected a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw Error(w.at(key) + ": expected a finite number");
  return d;
}

glm::dvec3 vec3(const json& v, const Where& w, const std::string& key) {
  if (!v.is_array() || v.size() != 3) throw Error(w.at(key) + ": expected 3 numbers [x, y, z]");
  return {number(v[0], w, key), number(v[1], w, key), number(v[2], w, key)};
}

// The same checks as the command line's camera flags (app/cli_options.cpp).
void check(const Camera& c, const Where& w) {
  if (!(c.fovyDeg > 0.0 && c.fovyDeg < 180.0)) throw Error(w.at("fovy") + ": must be in (0, 180) degrees");
  if (!(c.znear > 0.0) || !(c.zfar > c.znear)) throw Error(w.at("near") + ": need 0 < near < far");
  if (glm::length(c.eye - c.target) == 0.0) throw Error(w.at("eye") + ": eye and target must differ");
  if (glm::length(glm::cross(c.target - c.eye, c.up)) == 0.0)
    throw Error(w.at("up") + ": up must not be parallel to the view direction");
}

Camera flagEntry(const json& e, const Camera& base, const Where& w) {
  if (!e.is_object()) throw Error(w.at("") + ": expected an object with eye, target, up, fovy, near, far");
  Camera c = base;
  c.orthoHalfHeight = 0.0;
  c.viewProjOverride.reset();
  for (auto it = e.begin(); it != e.end(); ++it) {
    const std::string& k = it.key();
    if (k == "eye") c.eye = vec3(*it, w, k);
    else if (k == "target") c.target = vec3(*it, w, k);
    else if (k == "up") c.up = vec3(*it, w, k);
    else if (k == "fovy") c.fovyDeg = number(*it, w, k);
    else if (k == "near") c.znear = number(*it, w, k);
    else if (k == "far") c.zfar = number(*it, w, k);
    else throw Error(w.at(printable(k, 40)) + ": unknown key (expected eye, target, up, fovy, near, far)");
  }
  check(c, w);
  return c;
}

Camera nerfFrame(const json& f, const json* fileAngle, const Camera& base, const Where& w, int width, int height) {
  if (!f.is_object()) throw Error(w.at("") + ": expected an object with a transform_matrix");
  const auto m = f.find("transform_matrix");
  if (m == f.end()) throw Error(w.at("transform_matrix") + ": missing");
  if (!m->is_array() || m->size() != 4) throw Error(w.at("transform_matrix") + ": expected 4 rows of 4 numbers");
  double a[4][4];
  for (int r = 0; r < 4; ++r) {
    const json& row = (*m)[size_t(r)];
    if (!row.is_array() || row.size() != 4) throw Error(w.at("transform_matrix") + ": expected 4 rows of 4 numbers");
    for (int k = 0; k < 4; ++k) a[r][k] = number(row[size_t(k)], w, "transform_matrix");
  }
  const auto own = f.find("camera_angle_x");
  const json* angle = own != f.end() ? &*own : fileAngle;
  if (!angle) throw Error(w.at("camera_angle_x") + ": missing (in the file or the frame)");
  const double ax = number(*angle, w, "camera_angle_x");
  if (!(ax > 0.0 && ax < M_PI)) throw Error(w.at("camera_angle_x") + ": must be in (0, pi) radians");
  Camera c = base;
  c.orthoHalfHeight = 0.0;
  c.viewProjOverride.reset();
  // Columns of the camera-to-world matrix: x, y (up), z (backwards), position.
  c.eye = {a[0][3], a[1][3], a[2][3]};
  const glm::dvec3 back{a[0][2], a[1][2], a[2][2]};
  c.up = {a[0][1], a[1][1], a[2][1]};
  if (!(glm::length(back) > 0.0)) throw Error(w.at("transform_matrix") + ": its z axis is zero");
  c.target = c.eye - glm::normalize(back) * std::max(1.0, glm::length(base.target - base.eye));
  c.fovyDeg = glm::degrees(2.0 * std::atan(std::tan(ax / 2.0) * double(height) / double(width)));
  check(c, w);
  return c;
}

}  // namespace

std::vector<Camera> parseCameraList(const std::string& text, const std::string& name, const Camera& base, int width,
                                    int height) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    std::string m = e.what();
    for (char& ch : m)
      if (ch == '\n') ch = ' ';
    throw Error("--cameras " + printable(name) + ": not valid JSON (" + printable(m, 160) + ")");
  }
  std::vector<Camera> out;
  if (doc.is_array()) {
    if (doc.size() > kMaxCameraListViews)
      throw Error("--cameras " + printable(name) + ": " + std::to_string(doc.size()) + " views (at most " +
                  std::to_string(kMaxCameraListViews) + ")");
    for (size_t i = 0; i < doc.size(); ++i) out.push_back(flagEntry(doc[i], base, Where{name, i}));
  } else if (doc.is_object() && doc.contains("frames")) {
    const json& frames = doc["frames"];
    if (!frames.is_array()) throw Error("--cameras " + printable(name) + ": 'frames' must be a list");
    if (frames.size() > kMaxCameraListViews)
      throw Error("--cameras " + printable(name) + ": " + std::to_string(frames.size()) + " frames (at most " +
                  std::to_string(kMaxCameraListViews) + ")");
    const auto angle = doc.find("camera_angle_x");
    for (size_t i = 0; i < frames.size(); ++i)
      out.push_back(nerfFrame(frames[i], angle != doc.end() ? &*angle : nullptr, base, Where{name, i}, width, height));
  } else {
    throw Error("--cameras " + printable(name) +
                ": expected a list of cameras [{\"eye\": [x,y,z], \"target\": [...], ...}] or a NeRF transforms.json "
                "({\"camera_angle_x\": ..., \"frames\": [...]})");
  }
  if (out.empty()) throw Error("--cameras " + printable(name) + ": no views in the file");
  return out;
}

std::vector<Camera> loadCameraList(const std::string& path, const Camera& base, int width, int height) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error("--cameras " + printable(path) + ": not a readable file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("--cameras " + printable(path) + ": cannot open the file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0 || size > (std::streamoff(256) << 20))
    throw Error("--cameras " + printable(path) + ": not a readable file of at most 256 MiB");
  in.seekg(0);
  std::string text(size_t(size), '\0');
  if (!in.read(&text[0], size)) throw Error("--cameras " + printable(path) + ": read failed");
  return parseCameraList(text, path, base, width, height);
}

}  // namespace rast
