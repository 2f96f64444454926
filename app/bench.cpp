#include "app/bench.h"

#include "host/image/safe_output.h"

#include "backends/stage_timer.h"
#include "app/distribute.h"
#include "host/distributed/ranks.h"
#include "host/scene/animation.h"
#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"
#include "app/progress.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace rast {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct BenchRow {
  std::string scene, requested, method, backend, device;
  int width, height, frames;
  std::vector<std::pair<std::string, double>> stageMedianMs;
  double totalMedianMs, totalMinMs;
  double stagedMedianMs = 0.0;  // the sum of the stages, in the frames timed stage by stage
  // Host time to queue a frame's kernels (no wait): when it reaches the frame
  // time, the GPU waits on launches and the frame is bound by them.
  double enqueueMedianMs = 0.0;
  FrameStats stats;
};

// The device in one line: a GPU backend's "device: ..." line of
// deviceDescription(), else the CPU's model name and the threads used.
std::string deviceName() {
  std::istringstream lines(deviceDescription());
  for (std::string l; std::getline(lines, l);)
    if (l.rfind("device: ", 0) == 0) return l.substr(8);
  std::string model = "CPU";
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string l; std::getline(cpu, l);)
    if (l.rfind("model name", 0) == 0 && l.find(':') != std::string::npos) {
      model = l.substr(l.find(':') + 1);
      model.erase(0, model.find_first_not_of(' '));
      break;
    }
  return model + " (" + std::to_string(Exec().concurrency()) + " threads)";
}

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) o += c;
  }
  return o + "\"";
}

BenchRow benchOne(Renderer& r, const Camera& cam, const RenderSettings& rs, const BenchOptions& bo,
                  const std::string& sceneName) {
  // Warm-up frames grow every buffer to what this scene and view need.
  for (int i = 0; i < std::max(bo.warmup, 1); ++i) r.render(cam, rs);
  StageTimer timer, frameTimer;
  std::map<std::string, std::vector<double>> perStage;
  std::vector<std::string> order;
  std::vector<double> totals, staged, enqueues;
  const bool supersampled = rs.ssaa > 1 || rs.reference;
  Progress progress(std::string("rast: bench ") + toString(rs.raster) + ", frame");
  for (int i = 0; i < bo.frames; ++i) {
    progress.update(i + 1, bo.frames);
    if (supersampled) {
      // SSAA and the reference are many passes of the whole pipeline (each
      // checked for buffer growth): timed as one stage, wall clock to the end.
      Kokkos::Timer t;
      r.render(cam, rs);
      Exec().fence();
      const double ms = t.seconds() * 1e3;
      if (!perStage.count("supersampled")) order.push_back("supersampled");
      perStage["supersampled"].push_back(ms);
      totals.push_back(ms);
      continue;
    }
    // Each timed frame is rendered twice: once with an event between stages
    // (the stage medians) and once with events only around it (the frame
    // time): on a GPU the events between stages cost the frame a few
    // microseconds, which no frame outside a benchmark pays.
    double sum = 0.0;
    r.enqueue(cam, rs, &timer);
    for (const auto& [name, ms] : timer.finish()) {
      if (!perStage.count(name)) order.push_back(name);
      perStage[name].push_back(ms);
      sum += ms;
    }
    staged.push_back(sum);
    frameTimer.start();
    Kokkos::Timer queued;
    r.enqueue(cam, rs, nullptr);
    enqueues.push_back(queued.seconds() * 1e3);
    frameTimer.mark("frame");
    totals.push_back(frameTimer.finish().at(0).second);
  }
  BenchRow row;
  if (!r.lastFrameFit(&row.stats)) throw Error("internal: buffers overflowed during timed frames");
  row.scene = sceneName;
  row.requested = toString(rs.raster);
  row.method = toString(row.stats.method);
  row.backend = Exec::name();
  row.device = deviceName();
  row.width = rs.width;
  row.height = rs.height;
  row.frames = bo.frames;
  for (const auto& n : order) row.stageMedianMs.emplace_back(n, median(perStage[n]));
  row.totalMedianMs = median(totals);
  row.stagedMedianMs = median(staged.empty() ? totals : staged);
  row.enqueueMedianMs = median(enqueues);
  row.totalMinMs = totals.empty() ? 0.0 : *std::min_element(totals.begin(), totals.end());
  return row;
}

std::string jsonRow(const BenchRow& b) {
  char buf[512];
  std::string s = "{\"scene\": \"" + b.scene + "\", \"requested\": \"" + b.requested + "\", \"method\": \"" + b.method +
                  "\", \"backend\": \"" + b.backend + "\", \"device\": " + jsonString(b.device);
  // Drawn triangles per second of median frame time.
  std::snprintf(buf, sizeof buf, ", \"triangles_per_second\": %.6g",
                b.totalMedianMs > 0.0 ? b.stats.trianglesIn / (b.totalMedianMs * 1e-3) : 0.0);
  s += buf;
  // The visbuffer raster's layout: a block's rows on lanes (raster_visbuffer.cpp).
  if (b.stats.method == RasterMethod::VisBuffer) s += std::string(", \"row_lanes\": ") + (b.stats.rowLanes ? "true" : "false");
  std::snprintf(buf, sizeof buf,
                ", \"width\": %d, \"height\": %d, \"frames\": %d, \"total_median_ms\": %.6f, \"total_min_ms\": %.6f, \"enqueue_host_median_ms\": %.6f, \"staged_total_median_ms\": %.6f"
                ", \"triangles_in\": %u, \"triangles_raster\": %u, \"raster_work_items\": %u"
                ", \"device_bytes\": %zu, \"minimum_bytes\": %zu, \"film_bytes\": %zu, \"stages_median_ms\": {",
                b.width, b.height, b.frames, b.totalMedianMs, b.totalMinMs, b.enqueueMedianMs, b.stagedMedianMs, b.stats.trianglesIn, b.stats.rasterTris,
                b.stats.rasterWork, b.stats.deviceBytes, b.stats.minimumBytes, b.stats.filmBytes);
  s += buf;
  for (size_t i = 0; i < b.stageMedianMs.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s\"%s\": %.6f", i ? ", " : "", b.stageMedianMs[i].first.c_str(), b.stageMedianMs[i].second);
    s += buf;
  }
  return s + "}}";
}

}  // namespace

void BenchOptions::addTo(CLI::App& app) {
  app.add_option("--frames", frames, "timed frames (their median is reported)")->capture_default_str()->check(CLI::Range(1, 1000000));
  app.add_option("--warmup", warmup, "untimed frames first (grow buffers, warm caches)")->capture_default_str()->check(CLI::Range(0, 1000000));
  app.add_option("--json", json, "write the rows as a JSON array to this file");
  app.add_option("--csv", csv, "write the rows as CSV to this file");
  app.add_flag("--all-methods", allMethods, "bench every raster method, then auto (overrides --raster)");
  app.add_flag("--distribute", distribute, "under mpirun/srun: each rank draws its share of the scene, frames composited "
                                          "(sort-last; stages composite and merge; docs/distributed.md)");
  app.add_option("--methods", methods, "comma-separated raster methods to bench, e.g. visbuffer,binned,auto");
}

int runBench(const SceneOptions& so, const BenchOptions& bo) {
  RenderSettings rs = so.settings();
  if (bo.distribute) startDistributed();
  RunScene loaded;
  together(bo.distribute, [&] { loaded = loadRunScene(so, bo.distribute); });
  Scene& scene = loaded.scene;
  const Camera cam = loaded.camera;
  so.applySceneLook(scene, rs, /*still=*/false);
  const std::string sceneName = so.scene.empty() ? "builtin:default" : so.scene;
  std::printf("rast: bench %s at %dx%d on %s, camera %s\n", sceneName.c_str(), rs.width, rs.height, Exec::name(),
              cam.flags().c_str());
  std::unique_ptr<Renderer> rp;
  together(bo.distribute, [&] { rp = std::make_unique<Renderer>(scene, so.memoryBudget()); });
  Renderer& r = *rp;
  if (loaded.split) r.setSplit(loaded.split.get());
  std::vector<RasterMethod> methods = bo.allMethods ? allRasterMethods() : std::vector<RasterMethod>{rs.raster};
  if (bo.allMethods) methods.push_back(RasterMethod::Auto);
  if (!bo.methods.empty()) {
    methods.clear();
    std::stringstream ss(bo.methods);
    std::string m;
    while (std::getline(ss, m, ',')) methods.push_back(parseRaster(m));
  }
  std::vector<BenchRow> rows;
  for (RasterMethod m : methods) {
    rs.raster = m;
    frames(bo.distribute, [&] { rows.push_back(benchOne(r, cam, rs, bo, sceneName)); });
  }

  std::printf("%-16s", "method");
  for (const auto& s : rows[0].stageMedianMs) std::printf(" %10s", s.first.c_str());
  std::printf(" %10s %10s %12s %12s\n", "total", "min", "tris_raster", "device_MiB");
  for (const BenchRow& b : rows) {
    const std::string label = b.requested == b.method ? b.method : b.requested + "->" + b.method;
    std::printf("%-16s", label.c_str());
    for (const auto& s : b.stageMedianMs) std::printf(" %10.3f", s.second);
    std::printf(" %10.3f %10.3f %12u %12.1f\n", b.totalMedianMs, b.totalMinMs, b.stats.rasterTris,
                b.stats.deviceBytes / 1048576.0);
  }
  std::printf("(milliseconds, median of %d frames after %d warm-up; stages from frames timed stage by stage, total from "
              "as many frames timed whole; minimum needed %.1f MiB; float film and post buffers %.1f MiB)\n",
              bo.frames, bo.warmup, rows[0].stats.minimumBytes / 1048576.0, rows[0].stats.filmBytes / 1048576.0);

  if (bo.distribute && Ranks::rank() != 0) return 0;  // rank 0 writes the rows
  // An animated scene: what a new pose costs before its frame (docs/animation.md):
  // evaluating the animations and morphing on the host, then sending the pose
  // (draw matrices, joint palette, morphed vertices) into the renderer's buffers.
  if (scene.rig && !scene.rig->animations.empty()) {
    PoseRequest pr = so.poseRequest(scene).value_or(PoseRequest{});
    double a = 0.0, b = 0.0;
    for (const Animation& an : scene.rig->animations)
      if (pr.animation < 0 || &an == &scene.rig->animations[size_t(pr.animation)]) b = std::max(b, an.end);
    std::vector<double> evalMs, sendMs;
    for (int i = 0; i < bo.frames; ++i) {
      pr.time = a + (b - a) * i / std::max(1, bo.frames - 1);
      Kokkos::Timer t;
      poseScene(scene, pr, /*skinOnHost=*/false);
      evalMs.push_back(t.seconds() * 1e3);
      Kokkos::Timer u;
      r.updatePose(scene);
      Exec().fence();
      sendMs.push_back(u.seconds() * 1e3);
    }
    std::printf("animation: %.4f ms to pose (evaluate %zu animations, morph), %.4f ms to send the pose (median of %d poses "
                "over 0..%.3g s; skinning is in the vertex stage)\n",
                median(evalMs), scene.rig->animations.size(), median(sendMs), bo.frames, b);
  }

  // Written atomically (host/image/safe_output.h), as every output of rast.
  if (!bo.json.empty()) {
    std::ostringstream f;
    f << "[\n";
    for (size_t i = 0; i < rows.size(); ++i) f << "  " << jsonRow(rows[i]) << (i + 1 < rows.size() ? ",\n" : "\n");
    f << "]\n";
    const std::string text = f.str();
    writeFileAtomically(bo.json, text.data(), text.size());
  }
  if (!bo.csv.empty()) {
    std::ostringstream f;
    f << "scene,requested,method,backend,width,height,frames,total_median_ms,total_min_ms,triangles_in,triangles_raster,"
         "raster_work_items,device_bytes,minimum_bytes,film_bytes";
    for (const auto& s : rows[0].stageMedianMs) f << "," << s.first << "_median_ms";
    f << "\n";
    for (const BenchRow& b : rows) {
      f << b.scene << "," << b.requested << "," << b.method << "," << b.backend << "," << b.width << "," << b.height << "," << b.frames << ","
        << b.totalMedianMs << "," << b.totalMinMs << "," << b.stats.trianglesIn << "," << b.stats.rasterTris << ","
        << b.stats.rasterWork << "," << b.stats.deviceBytes << "," << b.stats.minimumBytes << "," << b.stats.filmBytes;
      for (const auto& s : b.stageMedianMs) f << "," << s.second;
      f << "\n";
    }
    const std::string text = f.str();
    writeFileAtomically(bo.csv, text.data(), text.size());
  }
  return 0;
}

}  // namespace rast
