#include "app/compare_cmd.h"

#include "host/image/image_io.h"
#include "host/image/image_metrics.h"
#include "host/image/safe_output.h"
#include "base/error.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace rast {
namespace {

std::vector<uint32_t> loadPng(const std::string& path, int& w, int& h) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw Error("cannot open '" + path + "': no such file");
  return readPng(path, w, h);
}

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') o += '\\', o += char(c);
    else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
    } else o += char(c);
  }
  return o + "\"";
}

std::string num(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no infinity (PSNR of identical images)
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

void CompareOptions::addTo(CLI::App& app) {
  app.add_option("reference", reference, "reference (ground truth) image, PNG")->required();
  app.add_option("test", test, "image to measure, PNG of the same size")->required();
  app.add_option("--ids", ids, "the reference's primitive ids (glref-ids .bin, e.g. from --aov primid=F.bin): "
                               "edge pixels are id boundaries; default: Sobel edges of the reference");
  app.add_option("--json", json, "also write the metrics as a JSON object to this file");
}

int runCompare(const CompareOptions& co) {
  int wa = 0, ha = 0, wb = 0, hb = 0;
  const std::vector<uint32_t> a = loadPng(co.reference, wa, ha);
  const std::vector<uint32_t> b = loadPng(co.test, wb, hb);
  if (wa != wb || ha != hb)
    throw Error("size mismatch: '" + co.reference + "' is " + std::to_string(wa) + "x" + std::to_string(ha) + ", '" +
                co.test + "' is " + std::to_string(wb) + "x" + std::to_string(hb));
  std::vector<uint32_t> ids;
  if (!co.ids.empty()) {
    struct stat st;
    if (::stat(co.ids.c_str(), &st) != 0) throw Error("cannot open '" + co.ids + "': no such file");
    int wi = 0, hi = 0;
    ids = readIdsBin(co.ids, wi, hi);
    if (wi != wa || hi != ha)
      throw Error("size mismatch: ids '" + co.ids + "' are " + std::to_string(wi) + "x" + std::to_string(hi) +
                  ", the images " + std::to_string(wa) + "x" + std::to_string(ha));
  }
  const ImageMetrics m = compareImages(a, b, wa, ha, co.ids.empty() ? nullptr : &ids);

  // The JSON first: an unwritable path fails before anything is printed.
  if (!co.json.empty()) {
    std::ostringstream f;  // then written atomically (host/image/safe_output.h)
    f << "{\"reference\": " << jsonString(co.reference) << ", \"test\": " << jsonString(co.test)
      << ", \"width\": " << m.width << ", \"height\": " << m.height << ", \"rmse_linear\": " << num(m.rmseLinear)
      << ", \"psnr_linear_db\": " << num(m.psnrLinear) << ", \"ssim\": " << num(m.ssim)
      << ", \"ssim_window\": " << m.ssimWindow << ", \"count_gt1\": " << m.countGt1
      << ", \"frac_gt1\": " << num(m.fracGt1) << ", \"count_gt8\": " << m.countGt8
      << ", \"frac_gt8\": " << num(m.fracGt8) << ", \"max_channel_diff\": " << m.maxChannelDiff
      << ", \"edge_rmse_linear\": " << num(m.edgeRmseLinear) << ", \"edge_pixels\": " << m.edgePixels
      << ", \"edge_source\": \"" << (m.edgesFromIds ? "ids" : "sobel") << "\"}\n";
    const std::string text = f.str();
    writeFileAtomically(co.json, text.data(), text.size());
  }
  std::printf("rast: compare %s (reference) vs %s, %dx%d\n", co.reference.c_str(), co.test.c_str(), wa, ha);
  std::printf("rmse_linear      %.6g\n", m.rmseLinear);
  std::printf("psnr_linear_db   %s\n", std::isfinite(m.psnrLinear) ? num(m.psnrLinear).c_str() : "inf");
  std::printf("ssim             %.6f   (luma, %dx%d Gaussian sigma 1.5)\n", m.ssim, m.ssimWindow, m.ssimWindow);
  std::printf("count_gt1        %llu   (max channel diff > 1/255)\n", (unsigned long long)m.countGt1);
  std::printf("frac_gt1         %.6g\n", m.fracGt1);
  std::printf("count_gt8        %llu   (max channel diff > 8/255)\n", (unsigned long long)m.countGt8);
  std::printf("frac_gt8         %.6g\n", m.fracGt8);
  std::printf("max_channel_diff %d/255\n", m.maxChannelDiff);
  std::printf("edge_rmse_linear %.6g   (%llu edge pixels, from %s)\n", m.edgeRmseLinear,
              (unsigned long long)m.edgePixels, m.edgesFromIds ? "ids" : "Sobel of the reference");
  return 0;
}

}  // namespace rast
