// In-between frames with OpenGL's warper, composed on the CPU (the pair read
// back, composed, the frame uploaded to be shown: the viewer's
// --frames-on-cpu) and kept on the GPU (session::FrameEngine::
// keepFramesOnGpu: a composition pass, the masks read back, the frame shown
// from its texture), each frame of the scene's default path drawn both ways
// in turn in one process (ratios hold on a shared machine), with the hole
// pass drawing every rectangle.
// Usage: gpu_frames_bench SCENE [SIZE] [FRAMES] [OUT.json]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/gl/context.h"
#include "core/gl/gl_api.h"
#include "core/machine.h"
#include "core/timer.h"
#include "keyframe/lod_builder.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "session/frame_engine.h"
#include "session/presets.h"

namespace {

double medianOf(std::vector<double> v) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Series {
  std::vector<double> pair, readback, compose, holes, show, total;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace hw;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE [SIZE] [FRAMES] [OUT.json]\n", argv[0]);
    return 2;
  }
  const int size = argc > 2 ? std::atoi(argv[2]) : 512;
  const int frames = argc > 3 ? std::atoi(argv[3]) : 61;
  if (size < 16 || size > 4096 || frames < 12)
    return std::fprintf(stderr, "SIZE in [16, 4096] and FRAMES >= 12 expected\n"), 2;
  auto scene = scenes::loadScene(argv[1]);
  if (!scene) return std::fprintf(stderr, "%s\n", scene.error().message.c_str()), 1;
  auto path = scenes::defaultPathFor(argv[1]);
  if (!path) return std::fprintf(stderr, "%s\n", path.error().message.c_str()), 1;
  path->width = path->height = size;
  path->frames = std::max(path->frames, frames);
  auto ctx = gl::createHeadlessContext();
  if (!ctx) return std::fprintf(stderr, "%s\n", ctx.error().message.c_str()), 1;

  session::WalkOptions wo = session::presetOptions(session::Preset::Default);
  wo.warper = warp::WarperChoice::Gl;
  wo.renderHoles = true;
  auto ec = session::FrameEngine::create(*scene, wo, false, false);
  auto eg = session::FrameEngine::create(*scene, wo, false, false);
  if (!ec || !eg) return std::fprintf(stderr, "engine: cannot be created\n"), 1;
  session::FrameEngine* engines[2] = {ec->get(), eg->get()};
  if (!engines[1]->keepFramesOnGpu(true))
    return std::fprintf(stderr, "frames on the GPU: refused\n"), 1;
  // What the viewer does with a frame composed on the CPU: upload it to show it.
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);

  const int every = 10;
  Series series[2];
  keyframe::LodBuilder lod;
  for (int k = 0; k + every < frames; k += every) {
    for (int id : {k, k + every}) {
      if (engines[0]->has(id)) continue;
      keyframe::Keyframe kf;
      keyframe::QuadMesh mesh;
      const Camera cam = path->cameraAt(id);
      if (!engines[0]->renderer().renderKeyframe(cam, kf).ok() ||
          !lod.build(kf, wo.lod, &mesh).ok())
        return std::fprintf(stderr, "keyframe %d: failed\n", id), 1;
      for (session::FrameEngine* e : engines)
        if (!e->upload(id, kf, mesh, cam.eye, nullptr).ok())
          return std::fprintf(stderr, "upload %d: failed\n", id), 1;
    }
    for (int f = k + 1; f < k + every; ++f) {
      const Camera cam = path->cameraAt(f);
      for (int turn = 0; turn < 2; ++turn) {
        const int which = (f + turn) % 2;  // alternate who goes first
        session::FrameEngine& e = *engines[which];
        Series& s = series[which];
        Stopwatch total;
        session::InBetweenStats st;
        if (!e.warp(cam, k, k + every, st, nullptr).ok())
          return std::fprintf(stderr, "warp %d: failed\n", f), 1;
        session::HolePassResult hr;
        if (!e.renderHoles(cam, nullptr, &hr).ok())
          return std::fprintf(stderr, "holes %d: failed\n", f), 1;
        Stopwatch show;
        if (!e.framesOnGpu()) {
          glBindTexture(GL_TEXTURE_2D, tex);
          glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
          glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE,
                          e.frame().colour.data());
        }
        glFinish();
        s.show.push_back(show.ms());
        s.total.push_back(total.ms());
        s.pair.push_back(st.warpAMs + st.warpBMs);
        s.readback.push_back(st.readbackMs);
        s.compose.push_back(st.composeMs);
        s.holes.push_back(hr.drawMs);
        e.present();
      }
    }
    for (session::FrameEngine* e : engines) e->releaseBefore(k + every);
  }
  glDeleteTextures(1, &tex);

  const char* names[2] = {"composed on the CPU (--frames-on cpu; auto on llvmpipe)",
                          "kept on the GPU (--frames-on gpu; auto on a GPU)"};
  nlohmann::json out;
  out["scene"] = argv[1];
  out["size"] = size;
  out["frames"] = series[0].total.size();
  const auto glString = [](GLenum name) {
    const auto* v = reinterpret_cast<const char*>(glGetString(name));
    return std::string(v ? v : "");
  };
  out["machine"] = machineInfo(glString(GL_RENDERER), glString(GL_VERSION));
  std::printf("%s, %dx%d, %zu in-between frames each way (medians, ms)\n", argv[1], size, size,
              series[0].total.size());
  std::printf("%-50s %7s %9s %8s %7s %7s %7s\n", "", "pair", "readback", "compose", "holes",
              "show", "total");
  for (int v = 0; v < 2; ++v) {
    const Series& s = series[v];
    nlohmann::json j;
    j["variant"] = names[v];
    j["pair_ms"] = medianOf(s.pair);
    j["readback_ms"] = medianOf(s.readback);
    j["compose_ms"] = medianOf(s.compose);
    j["holes_ms"] = medianOf(s.holes);
    j["show_ms"] = medianOf(s.show);
    j["total_ms"] = medianOf(s.total);
    out["variants"].push_back(j);
    std::printf("%-50s %7.2f %9.2f %8.2f %7.2f %7.2f %7.2f\n", names[v], medianOf(s.pair),
                medianOf(s.readback), medianOf(s.compose), medianOf(s.holes), medianOf(s.show),
                medianOf(s.total));
  }
  if (argc > 4) {
    std::ofstream f(argv[4]);
    f << out.dump(2) << "\n";
    if (!f) return std::fprintf(stderr, "%s: cannot be written\n", argv[4]), 1;
  }
  return 0;
}
