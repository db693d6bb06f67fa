#include "bench/disocclusion_study.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

#include "core/camera.h"
#include "core/json_util.h"
#include "core/metrics.h"
#include "core/progress.h"
#include "core/timer.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/lod_builder.h"
#include "report/html_report.h"
#include "scenes/loader.h"
#include "session/hole_pass.h"
#include "session/in_between.h"
#include "session/presets.h"
#include "warp/warper.h"

namespace hw::bench {

using nlohmann::json;

namespace {

struct Built {
  keyframe::CachedKeyframe kf;
  std::unique_ptr<warp::WarpSource> source;
};

bool insideView(const Camera& c, const glm::dvec3& p) {
  const ProjectedPoint q = c.project(p);
  return q.zEye > c.nearPlane && q.u >= 0 && q.v >= 0 && q.u < c.width && q.v < c.height;
}

// `out` = `base` with the pixels of `mask` taken from `from`.
void fillMasked(const Image<Rgba8>& base, const Image<Rgba8>& from, const Image<std::uint8_t>& mask,
                Image<Rgba8>& out) {
  out = base;
  for (std::size_t p = 0; p < mask.size(); ++p)
    if (mask.data()[p]) out.data()[p] = from.data()[p];
}

// Sums and per-frame lists of one way of filling the holes.
struct Variant {
  std::vector<double> psnr, psnrHoles, ms;
  long long filled = 0;  // hole pixels it filled
};

json variantJson(const Variant& v, long long holes) {
  return {
      {"psnr",
       {{"median", finiteOrNull(median(v.psnr))}, {"p5", finiteOrNull(percentile(v.psnr, 5.0))}}},
      {"psnr_holes_median", finiteOrNull(median(v.psnrHoles))},
      {"filled_share", holes > 0 ? json(static_cast<double>(v.filled) / holes) : json(nullptr)},
      {"ms_median", v.ms.empty() ? json(nullptr) : finiteOrNull(median(v.ms))}};
}

}  // namespace

Result<json> runDisocclusionPath(const scenes::Scene& scene, const std::string& label,
                                 const std::string& pathLabel, const scenes::CameraPath& pathIn,
                                 const DisocclusionOptions& opt) {
  scenes::CameraPath path = pathIn;
  if (opt.width > 0) path.width = opt.width;
  if (opt.height > 0) path.height = opt.height;
  std::vector<Camera> cams = path.cameras();
  if (opt.frames > 0 && static_cast<int>(cams.size()) > opt.frames)
    cams.resize(static_cast<std::size_t>(opt.frames));
  const int frames = static_cast<int>(cams.size());

  session::WalkOptions w = session::presetOptions(session::Preset::Default);
  keyframe::RenderOptions ropt;
  ropt.depthMode = w.depthMode;
  auto rendererR = keyframe::GeometryRenderer::create(scene, ropt);
  if (!rendererR) return rendererR.error();
  keyframe::GeometryRenderer& renderer = **rendererR;
  auto warperR = warp::Warper::create(w.warp);
  if (!warperR) return warperR.error();
  warp::Warper& warper = **warperR;
  session::InBetweenStep step(w.inBetween);
  session::HolePass holePass;
  keyframe::LodBuilder builder;
  const keyframe::MeshSpec spec{w.mesh, w.lod, w.tileSize};
  const keyframe::KeyframeSchedule schedule{frames, path.keyframeEvery, {}};
  const std::vector<int> keys = schedule.keyframes();

  std::map<int, Built> built;
  auto get = [&](int k, Built** out) -> Status {
    auto it = built.find(k);
    if (it == built.end()) {
      Built b;
      HW_TRY(keyframe::buildCachedKeyframe(renderer, builder, spec,
                                           cams[static_cast<std::size_t>(k)], k, b.kf));
      auto src = warper.upload(b.kf.keyframe, b.kf.mesh);
      if (!src) return src.error();
      b.source = std::move(*src);
      it = built.emplace(k, std::move(b)).first;
    }
    *out = &it->second;
    return {};
  };
  // The keyframe `by` places from k in the schedule (-1: none).
  auto neighbour = [&](int k, int by) {
    const auto at = std::find(keys.begin(), keys.end(), k) - keys.begin();
    const auto n = at + by;
    return n >= 0 && n < static_cast<long>(keys.size()) ? keys[static_cast<std::size_t>(n)] : -1;
  };

  gapfill::Frame frame, previous, work;
  bool havePrevious = false;
  keyframe::Keyframe ref;
  warp::Layer third;
  Image<std::uint8_t> occludedMask, mask;
  Image<Rgba8> filled;
  Variant copy, prev, next, rects, peel, exact;
  long long holeTotal = 0, outside = 0, occluded = 0, sky = 0;
  std::vector<double> holeShare, pairMs;
  json rows = json::array();
  Progress progress(opt.progress, frames, "disocclusion " + label + " " + pathLabel);

  for (int i = 0; i < frames; ++i) {
    progress.update(i);
    const Camera& cam = cams[static_cast<std::size_t>(i)];
    const auto [k0, k1] = schedule.bracket(i);
    for (auto it = built.begin(); it != built.end();)  // keep the pair and its neighbours
      it = it->first < neighbour(k0, -1) ? built.erase(it) : std::next(it);
    Built* a = nullptr;
    Built* b = nullptr;
    HW_TRY(get(k0, &a));
    if (k0 == k1) {
      session::showKeyframe(a->kf.keyframe.colour, frame);
      std::swap(previous, frame);
      havePrevious = true;
      continue;
    }
    HW_TRY(get(k1, &b));
    const int fg =
        gapfill::chooseForeground(cam.eye, a->kf.keyframe.camera.eye, b->kf.keyframe.camera.eye);
    Built* f = fg == 0 ? a : b;
    Built* g = fg == 0 ? b : a;
    session::InBetweenStats st;
    Stopwatch pairSw;
    HW_TRY(step.draw(warper, *f->source, g->source.get(), cam, havePrevious ? &previous : nullptr,
                     nullptr, frame, st));
    pairMs.push_back(pairSw.ms());
    HW_TRY(renderer.renderKeyframe(cam, ref));

    const Image<std::uint8_t>& holes = frame.holesBefore;
    occludedMask.resize(cam.width, cam.height);
    long long h = 0, hOut = 0, hOcc = 0, hSky = 0;
    // The holes, by where the reference's surface there lies: sky, outside
    // both keyframes' views, or inside one of them (occluded there).
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        bool occ = false;
        if (holes(x, y)) {
          ++h;
          if (!ref.covered(x, y)) {
            ++hSky;
          } else {
            const glm::dvec3 p = cam.unproject(x + 0.5, y + 0.5, ref.eyeZ(x, y));
            occ = insideView(a->kf.keyframe.camera, p) || insideView(b->kf.keyframe.camera, p);
            ++(occ ? hOcc : hOut);
          }
        }
        occludedMask(x, y) = occ ? 1 : 0;
      }
    holeTotal += h;
    outside += hOut;
    occluded += hOcc;
    sky += hSky;
    holeShare.push_back(static_cast<double>(h) / static_cast<double>(holes.size()));

    auto score = [&](Variant& v, const Image<Rgba8>& img, long long filledPx, double ms) {
      const double p = psnrCapped(img, ref.colour);
      v.psnr.push_back(p);
      if (h > 0) v.psnrHoles.push_back(psnrCapped(img, ref.colour, holes));
      v.filled += filledPx;
      if (ms >= 0) v.ms.push_back(ms);
      return p;
    };
    json row = {{"frame", i},      {"k0", k0},         {"k1", k1},   {"holes", h},
                {"outside", hOut}, {"occluded", hOcc}, {"sky", hSky}};
    row["psnr_copy"] = finiteOrNull(score(copy, frame.colour, 0, -1));

    // A third keyframe: the one before the pair, then the one after it.
    for (int side : {-1, +1}) {
      const int k3 = neighbour(side < 0 ? k0 : k1, side);
      Variant& v = side < 0 ? prev : next;
      const std::string name = side < 0 ? "prev" : "next";
      if (k3 < 0) {  // none on this side: the pair's frame as it is
        row[name + "_filled"] = 0;
        row["psnr_" + name] = finiteOrNull(score(v, frame.colour, 0, -1));
        continue;
      }
      Built* t = nullptr;
      HW_TRY(get(k3, &t));
      warp::WarpStats ws;
      HW_TRY(warper.warp(*t->source, cam, third, &ws));
      long long n = 0;
      mask.resize(cam.width, cam.height);
      for (std::size_t p = 0; p < holes.size(); ++p) {
        mask.data()[p] = holes.data()[p] && third.coverage.data()[p] ? 1 : 0;
        n += mask.data()[p];
      }
      fillMasked(frame.colour, third.colour, mask, filled);
      row[name + "_filled"] = n;
      row["psnr_" + name] = finiteOrNull(score(v, filled, n, ws.drawMs + ws.readbackMs));
    }

    // The default preset's hole rectangles (every one found).
    work = frame;
    session::HolePassResult hr;
    HW_TRY(holePass.run(renderer, cam, work, step, session::holeTiling(session::WalkOptions{}), {},
                        &hr));
    row["psnr_hole_rects"] = finiteOrNull(score(rects, work.colour, hr.holes, hr.drawMs));
    row["hole_rects_ms"] = hr.drawMs;

    // Upper bounds: exact where a keyframe of the pair sees the surface's
    // place (depth peeling at best), and exact everywhere.
    fillMasked(frame.colour, ref.colour, occludedMask, filled);
    row["psnr_peel_bound"] = finiteOrNull(score(peel, filled, hOcc, -1));
    fillMasked(frame.colour, ref.colour, holes, filled);
    row["psnr_exact_holes"] = finiteOrNull(score(exact, filled, h, -1));
    rows.push_back(std::move(row));

    std::swap(previous, frame);
    havePrevious = true;
  }
  progress.update(frames);

  // The frames with the most holes (the tenth of the path, at least one).
  std::vector<std::size_t> order(rows.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return rows[x]["holes"].get<long long>() > rows[y]["holes"].get<long long>();
  });
  order.resize(std::min(order.size(), std::max<std::size_t>(1, order.size() / 10)));
  json worst = json::object();
  for (const char* key : {"psnr_copy", "psnr_prev", "psnr_next", "psnr_hole_rects",
                          "psnr_peel_bound", "psnr_exact_holes"}) {
    std::vector<double> v;
    for (std::size_t k : order)
      if (rows[k][key].is_number()) v.push_back(rows[k][key].get<double>());
    worst[key] = finiteOrNull(median(v));
  }
  json worstFrames = json::array();
  for (std::size_t k : order) worstFrames.push_back(rows[k]["frame"]);

  const double ht = static_cast<double>(std::max<long long>(1, holeTotal));
  json summary = {
      {"in_between_frames", rows.size()},
      {"keyframe_every", path.keyframeEvery},
      {"resolution", {cams.empty() ? 0 : cams[0].width, cams.empty() ? 0 : cams[0].height}},
      {"hole_share",
       {{"median", finiteOrNull(median(holeShare))},
        {"p95", finiteOrNull(percentile(holeShare, 95.0))},
        {"max", holeShare.empty() ? json(nullptr)
                                  : json(*std::max_element(holeShare.begin(), holeShare.end()))}}},
      {"hole_pixels", holeTotal},
      {"holes_outside_share", holeTotal ? json(outside / ht) : json(nullptr)},
      {"holes_occluded_share", holeTotal ? json(occluded / ht) : json(nullptr)},
      {"holes_sky_share", holeTotal ? json(sky / ht) : json(nullptr)},
      {"pair_ms_median", finiteOrNull(median(pairMs))},
      {"copy", variantJson(copy, holeTotal)},
      {"third_prev", variantJson(prev, holeTotal)},
      {"third_next", variantJson(next, holeTotal)},
      {"hole_rects", variantJson(rects, holeTotal)},
      {"peel_bound", variantJson(peel, holeTotal)},
      {"exact_holes", variantJson(exact, holeTotal)},
      {"worst_tenth", {{"frames", worstFrames}, {"psnr_median", worst}}}};
  return json{{"scene", label}, {"path", pathLabel}, {"frames", rows}, {"summary", summary}};
}

Result<json> runDisocclusionStudy(const DisocclusionOptions& opt) {
  json paths = json::array(), unavailable = json::array();
  for (const SceneCase& c : opt.cases) {
    auto scene = scenes::loadScene(c.spec);
    auto path = c.path.empty() ? scenes::defaultPathFor(c.spec) : scenes::loadCameraPath(c.path);
    if (!scene || !path) {
      unavailable.push_back({{"scene", c.spec},
                             {"path", c.path},
                             {"reason", !scene ? scene.error().message : path.error().message}});
      continue;
    }
    auto r = runDisocclusionPath(*scene, c.spec, c.path.empty() ? "default" : c.path, *path, opt);
    if (!r) return r.error();
    paths.push_back(std::move(*r));
  }
  return json{{"paths", paths}, {"unavailable", unavailable}};
}

std::string disocclusionCsv(const json& study) {
  static const char* cols[] = {"frame",
                               "k0",
                               "k1",
                               "holes",
                               "outside",
                               "occluded",
                               "sky",
                               "prev_filled",
                               "next_filled",
                               "psnr_copy",
                               "psnr_prev",
                               "psnr_next",
                               "psnr_hole_rects",
                               "hole_rects_ms",
                               "psnr_peel_bound",
                               "psnr_exact_holes"};
  std::string out = "scene,path";
  for (const char* c : cols) out += std::string(",") + c;
  out += "\n";
  for (const json& p : study["paths"])
    for (const json& r : p["frames"]) {
      out += p["scene"].get<std::string>() + "," + p["path"].get<std::string>();
      for (const char* c : cols) {
        out += ",";
        if (!r.contains(c) || r[c].is_null()) continue;
        out += r[c].is_number_integer() ? std::to_string(r[c].get<long long>())
                                        : report::fmt(r[c].get<double>(), 3);
      }
      out += "\n";
    }
  return out;
}

}  // namespace hw::bench
