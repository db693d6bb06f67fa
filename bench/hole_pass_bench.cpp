// The hole pass on the hole masks a walk saved (walk --save-frames writes
// holes/NNNN.png), drawn in turn in one process (ratios hold on a shared
// machine) by renderers whose scenes are cut into clusters of two sizes, by
// one drawing from the simplified copy (RenderOptions::simplifiedRects), and
// with every rectangle cut to one pixel (the pass's fixed cost): the same
// rectangles the walk draws (gapfill::holeRects with the walk's tile
// settings), the same cameras.
// Usage: hole_pass_bench SCENE HOLES_DIR [PATH.json]
#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/timer.h"
#include "gapfill/hole_rects.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "session/walk.h"

int main(int argc, char** argv) {
  using namespace hw;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SCENE HOLES_DIR [PATH.json]\n", argv[0]);
    return 2;
  }
  auto scene = scenes::loadScene(argv[1]);
  if (!scene) return std::fprintf(stderr, "%s\n", scene.error().message.c_str()), 1;
  auto path = argc > 3 ? scenes::loadCameraPath(argv[3]) : scenes::defaultPathFor(argv[1]);
  if (!path) return std::fprintf(stderr, "%s\n", path.error().message.c_str()), 1;
  auto ctx = gl::createHeadlessContext();
  if (!ctx) return std::fprintf(stderr, "%s\n", ctx.error().message.c_str()), 1;
  struct Variant {
    const char* name;
    keyframe::RenderOptions options;
    std::unique_ptr<keyframe::GeometryRenderer> renderer;
    std::vector<double> ms, triangles, draws;
  };
  std::vector<Variant> variants(3);
  variants[0].name = "clusters <= 512 triangles (default)";
  variants[1].name = "clusters <= 64 triangles, <= 0.25 units";
  variants[1].options.clusters.maxTriangles = 64;
  variants[1].options.clusters.minTriangles = 16;
  variants[1].options.clusters.maxExtent = 0.25f;
  variants[2].name = "default clusters, simplified copy";
  variants[2].options.simplifiedRects = true;
  for (Variant& v : variants) {
    auto r = keyframe::GeometryRenderer::create(*scene, v.options);
    if (!r) return std::fprintf(stderr, "%s\n", r.error().message.c_str()), 1;
    v.renderer = std::move(*r);
  }
  std::vector<gapfill::HoleRect> rects;
  std::vector<std::uint32_t> scratch;
  std::vector<PixelRect> px, tiny;
  std::vector<Image<Rgba8>> outs;
  std::vector<double> area, tinyMs;
  // Round 0 warms up (textures, JIT); round 1 is timed.
  for (int round = 0; round < 2; ++round) {
    for (int f = 0; f < path->frames; ++f) {
      char name[4096];
      std::snprintf(name, sizeof name, "%s/%04d.png", argv[2], f);
      auto img = readPng(name);
      if (!img) continue;
      if (img->width() != path->width || img->height() != path->height)
        return std::fprintf(stderr, "%s: %dx%d, expected the path's %dx%d\n", name, img->width(),
                            img->height(), path->width, path->height),
               1;
      Image<std::uint8_t> mask(img->width(), img->height());
      for (std::size_t p = 0; p < img->size(); ++p) mask.data()[p] = img->data()[p].r > 128;
      const session::WalkOptions defaults;
      gapfill::holeRects(mask, defaults.holeTilePx,
                         session::WalkOptions::holeTileMinPixels(defaults.holeTilePx),
                         std::numeric_limits<int>::max(), rects, scratch);
      if (rects.empty()) continue;
      if (outs.size() < rects.size()) outs.resize(rects.size());
      px.clear();
      double a = 0;
      for (const auto& h : rects) px.push_back(h.rect), a += h.rect.area();
      if (round == 1) area.push_back(a);
      const Camera cam = path->cameraAt(f);
      // The pass's fixed cost: as many rectangles, each cut to its first pixel.
      tiny.clear();
      for (const auto& r : px) tiny.push_back(PixelRect{r.x0, r.y0, r.x0 + 1, r.y0 + 1});
      {
        keyframe::RenderStats st;
        auto s = variants[0].renderer->renderColourRects(
            cam, tiny.data(), static_cast<int>(tiny.size()), outs.data(), &st);
        if (!s.ok()) return std::fprintf(stderr, "%s\n", s.error().message.c_str()), 1;
        if (round == 1) tinyMs.push_back(st.drawMs);
      }
      for (Variant& v : variants) {
        keyframe::RenderStats st;
        auto s = v.renderer->renderColourRects(cam, px.data(), static_cast<int>(px.size()),
                                               outs.data(), &st);
        if (!s.ok()) return std::fprintf(stderr, "%s\n", s.error().message.c_str()), 1;
        if (round == 1) {
          v.ms.push_back(st.drawMs);
          v.triangles.push_back(static_cast<double>(st.trianglesDrawn));
          v.draws.push_back(static_cast<double>(st.drawCalls));
        }
      }
    }
  }
  std::printf("%s: %zu frames with hole rectangles, median %.0f rectangle px\n", argv[1],
              area.size(), median(area));
  for (const Variant& v : variants)
    std::printf("  %-42s draw ms median %6.2f   triangles median %8.0f   draw calls median %5.0f\n",
                v.name, median(v.ms), median(v.triangles), median(v.draws));
  std::printf("  %-42s draw ms median %6.2f\n", "the same rectangles cut to 1x1 pixel",
              median(tinyMs));
  return 0;
}
