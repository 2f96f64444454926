#include "app/ssao_error_cmd.h"

#include "backends/stage_timer.h"
#include "host/image/ao_reference.h"
#include "host/image/image_io.h"
#include "host/image/safe_output.h"
#include "pipeline/post/ssao.h"
#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"
#include "app/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rast {

void SsaoErrorOptions::addTo(CLI::App& app) {
  app.add_option("--samples", samples, "SSAO sample counts to measure, comma-separated")->capture_default_str();
  app.add_option("--error-size", errorSize, "image size WxH of the error measurement")->capture_default_str();
  app.add_option("--rays", rays, "reference rays per pixel")->capture_default_str()->check(CLI::Range(1, 65536));
  app.add_option("--frames", frames, "timed frames per sample count (median)")->capture_default_str()->check(CLI::Range(1, 100000));
  app.add_option("--warmup", warmup, "untimed frames first")->capture_default_str()->check(CLI::Range(0, 100000));
  app.add_option("--csv", csv, "write the rows as CSV to this file");
  app.add_option("--reference-out", referenceOut, "write the reference AO (at --error-size) to this PFM");
}

int runSsaoError(const SceneOptions& so, const SsaoErrorOptions& o) {
  RenderSettings rs = so.settings();
  rs.post.ssao = true;
  std::vector<int> counts;
  {
    std::stringstream ss(o.samples);
    for (std::string it; std::getline(ss, it, ',');) {
      char* end = nullptr;
      const long v = std::strtol(it.c_str(), &end, 10);
      if (it.empty() || *end || v < 1 || v > 256) throw Error("--samples: expected counts in 1..256, got '" + o.samples + "'");
      counts.push_back(int(v));
    }
  }
  int ew = 0, eh = 0;
  char x = 0, extra = 0;
  if (std::sscanf(o.errorSize.c_str(), "%d%c%d%c", &ew, &x, &eh, &extra) != 3 || x != 'x' || ew < 1 || eh < 1 ||
      ew > 4096 || eh > 4096)
    throw Error("--error-size: expected WxH up to 4096x4096, got '" + o.errorSize + "'");
  // Outputs checked before the long measurement (written at its end).
  if (!o.csv.empty()) checkOutputPath(o.csv, "--csv");
  if (!o.referenceOut.empty()) checkOutputPath(o.referenceOut, "--reference-out");
  const Scene scene = loadSceneArg(so.scene);
  const Camera cam = so.camera(scene);
  so.applySceneLook(scene, rs, /*still=*/false);
  const float radius = ssaoRadiusFor(rs.post, glm::length(cam.eye - cam.target));
  rs.post.ssaoRadius = radius;

  RenderSettings es = rs;
  es.width = ew;
  es.height = eh;
  Renderer re(scene);
  re.render(cam, es);
  const std::vector<float4> geom = re.geometryBottomUp();
  Kokkos::Timer t;
  const std::vector<float> ref = rayTracedAo(scene, cam, ew, eh, geom, radius, o.rays);
  std::printf("rast: reference AO at %dx%d, %d rays per pixel, radius %g: %.1f s\n", ew, eh, o.rays, radius, t.seconds());

  if (!o.referenceOut.empty()) writePfm(o.referenceOut, ew, eh, 1, ref.data());
  Renderer rt(scene);
  std::printf("%8s %10s %10s %10s\n", "samples", "ssao_ms", "rmse", "mean_abs");
  std::ostringstream csv;  // written atomically at the end (host/image/safe_output.h)
  if (!o.csv.empty()) {
    csv << "scene,backend,width,height,error_width,error_height,radius,reference_rays,samples,ssao_median_ms,rmse,mean_abs\n";
  }
  for (int n : counts) {
    es.post.ssaoSamples = n;
    re.render(cam, es);
    const std::vector<float> ao = re.aoBottomUp();
    double se = 0.0, ae = 0.0;
    size_t covered = 0;
    for (size_t i = 0; i < ao.size(); ++i) {
      if (!(geom[i].w > 0.0f)) continue;
      const double d = double(ao[i]) - double(ref[i]);
      se += d * d;
      ae += std::abs(d);
      ++covered;
    }
    const double rmse = covered ? std::sqrt(se / covered) : 0.0, mae = covered ? ae / covered : 0.0;
    // Cost of the pass at the timing size (--size).
    rs.post.ssaoSamples = n;
    for (int i = 0; i < std::max(o.warmup, 1); ++i) rt.render(cam, rs);
    StageTimer timer;
    std::vector<double> ms;
    for (int i = 0; i < o.frames; ++i) {
      rt.enqueue(cam, rs, &timer);
      for (const auto& [name, v] : timer.finish())
        if (name == "ssao") ms.push_back(v);
    }
    std::sort(ms.begin(), ms.end());
    const double med = ms.empty() ? 0.0 : ms[ms.size() / 2];
    std::printf("%8d %10.3f %10.4f %10.4f\n", n, med, rmse, mae);
    if (!o.csv.empty())
      csv << (so.scene.empty() ? "builtin:default" : so.scene) << "," << Exec::name() << "," << rs.width << "," << rs.height
          << "," << ew << "," << eh << "," << radius << "," << o.rays << "," << n << "," << med << "," << rmse << "," << mae
          << "\n";
  }
  if (!o.csv.empty()) {
    const std::string text = csv.str();
    writeFileAtomically(o.csv, text.data(), text.size());
  }
  return 0;
}

}  // namespace rast
