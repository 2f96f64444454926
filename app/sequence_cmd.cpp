// Frame sequences for `rast render`: animation frames (--frames START:END:FPS),
// a camera orbit (--turntable N) or both, from one Renderer (the scene is
// uploaded once; each frame sends its pose: host/scene/animation.h), written
// as numbered PNGs or piped as raw RGBA into Debian's ffmpeg for a video. The
// camera is framed once, on the union of every frame's posed bounds, so the
// sequence does not jump; every output is checked before the first frame.
#include "app/sequence_cmd.h"

#include "app/progress.h"
#include "host/image/image_io.h"
#include "host/image/safe_output.h"
#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace rast {

std::vector<double> frameTimes(const std::string& spec, double* fps) {
  double a = 0, b = 0, f = 0;
  char c1 = 0, c2 = 0, extra = 0;
  if (std::sscanf(spec.c_str(), "%lf%c%lf%c%lf%c", &a, &c1, &b, &c2, &f, &extra) != 5 || c1 != ':' || c2 != ':')
    throw Error("--frames: expected START:END:FPS (seconds, seconds, frames per second), got '" + printable(spec) + "'");
  if (!std::isfinite(a) || !std::isfinite(b) || !(b >= a)) throw Error("--frames: need finite START <= END");
  if (!(f > 0.0 && f <= 1000.0)) throw Error("--frames: FPS must be in (0, 1000]");
  const double n = std::floor((b - a) * f + 1e-6) + 1.0;
  if (n > 100000.0) throw Error("--frames: more than 100000 frames");
  std::vector<double> t;
  for (int i = 0; i < int(n); ++i) t.push_back(a + i / f);  // i / f: no drift from repeated sums
  if (fps) *fps = f;
  return t;
}

namespace {

enum class OutKind { Pattern, Video };

// "out_%04d.png" -> the position and width of its one %d; throws for any other %.
struct Pattern {
  std::string before, after;
  int width = 0;
};

std::optional<Pattern> parsePattern(const std::string& s) {
  std::optional<Pattern> p;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') continue;
    size_t j = i + 1;
    if (j < s.size() && s[j] == '%') {  // a literal %
      ++i;
      continue;
    }
    int width = 0;
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j])) && width < 100) width = width * 10 + (s[j++] - '0');
    if (j >= s.size() || s[j] != 'd' || p) throw Error("-o: a sequence takes one %d or %0Nd in the file name, got '" + printable(s) + "'");
    p = Pattern{s.substr(0, i), s.substr(j + 1), width};
    i = j;
  }
  return p;
}

std::string unescape(const std::string& s) {
  std::string o;
  for (size_t i = 0; i < s.size(); ++i) {
    o += s[i];
    if (s[i] == '%' && i + 1 < s.size() && s[i + 1] == '%') ++i;
  }
  return o;
}

std::string frameName(const Pattern& p, int i) {
  char b[32];
  std::snprintf(b, sizeof b, "%0*d", p.width, i);
  return unescape(p.before) + b + unescape(p.after);
}

std::string lowerExt(const std::string& s) {
  const auto dot = s.rfind('.');
  std::string e = dot == std::string::npos ? "" : s.substr(dot + 1);
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::string findOnPath(const std::string& exe) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::string f = (dir.empty() ? "." : dir) + "/" + exe;
    if (access(f.c_str(), X_OK) == 0) return f;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return "";
}

// ffmpeg reading raw RGBA frames on its stdin, writing a temporary file beside
// the output that is renamed into place only when ffmpeg succeeds.
class FfmpegPipe {
 public:
  FfmpegPipe(const std::string& out, int w, int h, double fps) : out_(out), temp_(out + ".rast-partial") {
    const std::string exe = findOnPath("ffmpeg");
    if (exe.empty())
      throw Error("-o " + printable(out) + ": video output needs ffmpeg, which is not on PATH (apt-get install ffmpeg), "
                  "or write images with -o out_%04d.png");
    const std::string ext = lowerExt(out);
    char size[32], rate[32];
    std::snprintf(size, sizeof size, "%dx%d", w, h);
    std::snprintf(rate, sizeof rate, "%.9g", fps);
    std::vector<std::string> args = {exe, "-nostdin", "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo",
                                     "-pix_fmt", "rgba", "-s", size, "-r", rate, "-i", "pipe:0"};
    if (ext == "mp4") args.insert(args.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-f", "mp4"});
    else if (ext == "webm") args.insert(args.end(), {"-c:v", "libvpx-vp9", "-pix_fmt", "yuv420p", "-f", "webm"});
    else args.insert(args.end(), {"-f", "gif"});
    args.push_back(temp_);
    int fds[2];
    if (pipe(fds) != 0) throw Error(std::string("cannot open a pipe to ffmpeg: ") + std::strerror(errno));
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[0], 0);
    posix_spawn_file_actions_addclose(&fa, fds[1]);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int rc = posix_spawn(&pid_, exe.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fds[0]);
    if (rc != 0) {
      close(fds[1]);
      throw Error("cannot start ffmpeg: " + std::string(std::strerror(rc)));
    }
    fd_ = fds[1];
    oldPipe_ = std::signal(SIGPIPE, SIG_IGN);  // a dying ffmpeg is an Error, not a signal
  }
  ~FfmpegPipe() {
    if (fd_ >= 0) close(fd_);
    if (pid_ > 0) waitpid(pid_, nullptr, 0);
    if (!done_) unlink(temp_.c_str());
    std::signal(SIGPIPE, oldPipe_);
  }
  void frame(const std::vector<uint32_t>& rgba) {
    const char* p = reinterpret_cast<const char*>(rgba.data());
    size_t n = rgba.size() * 4;
    while (n > 0) {
      const ssize_t k = write(fd_, p, n);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) throw Error("ffmpeg stopped taking frames for " + printable(out_) + " (its message is above)");
      p += k;
      n -= size_t(k);
    }
  }
  void finish() {
    close(fd_);
    fd_ = -1;
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw Error("ffmpeg failed to write " + printable(out_) + " (its message is above)");
    if (std::rename(temp_.c_str(), out_.c_str()) != 0) throw Error("cannot rename the video into " + printable(out_) + ": " + std::strerror(errno));
    done_ = true;
  }

 private:
  std::string out_, temp_;
  pid_t pid_ = -1;
  int fd_ = -1;
  bool done_ = false;
  void (*oldPipe_)(int) = SIG_DFL;
};

}  // namespace

int runSequence(const SceneOptions& so, const SequenceOptions& seq, const std::string& out) {
  RenderSettings rs = so.settings();
  if (seq.turntable < 0 || seq.turntable > 100000) throw Error("--turntable: frames per orbit must be 1..100000");
  double fps = 30.0;
  std::vector<double> times = seq.frames.empty() ? std::vector<double>{} : frameTimes(seq.frames, &fps);
  if (times.empty()) times.assign(size_t(seq.turntable), so.time.value_or(0.0));
  const std::string ext = lowerExt(out);
  const bool video = ext == "mp4" || ext == "webm" || ext == "gif";
  const std::optional<Pattern> pattern = video ? std::nullopt : parsePattern(out);
  if (!video && !pattern) throw Error("-o: a sequence of " + std::to_string(times.size()) + " frames needs a %d in the file name "
                                      "(out_%04d.png) or a video (.mp4, .webm, .gif)");
  if (!video && ext != "png") throw Error("-o: sequence frames are written as PNG (out_%04d.png)");
  const std::string first = video ? out : frameName(*pattern, 0);
  checkOutputPath(first, "-o");
  OutputSet outputs;
  outputs.addOutput(first, "-o");
  if (!so.scene.empty() && so.scene.rfind("builtin:", 0) != 0) outputs.addInput(so.scene, "the scene file");
  outputs.check();
  Scene scene = loadSceneArg(so.scene, so.loadOptions());
  for (const std::string& f : scene.sourceFiles) outputs.addInput(f, "a file the scene reads");
  outputs.check();
  std::optional<PoseRequest> pose = so.poseRequest(scene);
  const bool animated = scene.rig && !scene.rig->animations.empty() && !seq.frames.empty();
  if (animated && !pose) pose = PoseRequest{};
  // The camera frames every pose of the sequence at once.
  Scene box;
  box.camera = scene.camera;
  box.cameras = scene.cameras;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (double t : times) {
    if (pose) {
      if (animated) pose->time = t;
      poseScene(scene, *pose);
    }
    glm::dvec3 a, b;
    scene.worldBounds(a, b);
    lo = glm::min(lo, a);
    hi = glm::max(hi, b);
    if (!animated) break;
  }
  addLinePrim(box, {float3{float(lo.x), float(lo.y), float(lo.z)}, float3{float(hi.x), float(hi.y), float(hi.z)}}, nullptr, {}, {0, 1}, -1);
  box.draws.push_back(Draw{0, glm::dmat4(1.0)});
  const Camera cam0 = so.camera(box);
  so.applySceneLook(scene, rs, /*still=*/false);
  if (!so.cameraGiven()) std::printf("rast: camera (%s) %s\n", cameraOrigin(scene), cam0.flags().c_str());
  Renderer r(scene, so.memoryBudget());
  std::unique_ptr<FfmpegPipe> ff;
  if (video) ff = std::make_unique<FfmpegPipe>(out, rs.width, rs.height, fps);
  Progress progress("rast: frames");
  for (size_t i = 0; i < times.size(); ++i) {
    if (animated) {
      pose->time = times[i];
      poseScene(scene, *pose, /*skinOnHost=*/false);  // the vertex stage skins
      r.updatePose(scene);
    }
    Camera cam = cam0;
    if (seq.turntable > 0) {
      const double angle = 2.0 * 3.14159265358979323846 * double(i % size_t(seq.turntable)) / seq.turntable;
      const glm::dmat4 rot = glm::rotate(glm::dmat4(1.0), angle, glm::normalize(cam0.up));
      cam.eye = cam0.target + glm::dvec3(rot * glm::dvec4(cam0.eye - cam0.target, 0.0));
    }
    r.render(cam, rs);
    if (ff) {
      ff->frame(r.colorTopDown());
    } else {
      const std::string name = frameName(*pattern, int(i));
      if (i > 0) checkOutputPath(name, "-o");
      AtomicFile f(name);
      writePng(f, rs.width, rs.height, r.colorTopDown());
      f.commit();
    }
    if (progress.active()) progress.update(int(i + 1), int(times.size()));
  }
  if (ff) ff->finish();
  std::printf("rast: wrote %zu frames to %s (%dx%d)\n", times.size(), printable(out).c_str(), rs.width, rs.height);
  return 0;
}

}  // namespace rast
