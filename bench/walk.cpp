#include "bench/walk.h"
#include "bench/frame_budget.h"
#include "bench/json_util.h"
#include "bench/plot.h"
#include "bench/progress.h"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "core/file_io.h"
#include "core/safe_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "gapfill/age.h"
#include "keyframe/gl/async_keyframes.h"
#include "keyframe/keyframe_cache.h"

namespace hw::bench {
namespace {

using nlohmann::json;

std::string frameName(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d.png", i);
  return buf;
}

json stats(const std::vector<double>& v) {
  return {{"median", finiteOrNull(median(v))},
          {"p5", finiteOrNull(percentile(v, 5))},
          {"p95", finiteOrNull(percentile(v, 95))},
          {"min", finiteOrNull(percentile(v, 0))},
          {"max", finiteOrNull(percentile(v, 100))},
          {"count", v.size()}};
}

// Estimated cost of a scissored geometry render (GeometryRenderer::
// renderColourRect) of p pixels, copy into the frame included:
// scale · (fixed + perPixel · p) · (1 + kMargin). fixed and perPixel come from
// two renders measured at warm-up (a tile and the whole image); scale follows
// the measured / estimated ratio of each refresh (exponential average), so
// the estimate tracks the scene and the load.
struct RefreshCostModel {
  static constexpr double kMargin = 0.1;  // headroom against timing noise
  static constexpr double kAlpha = 0.25;  // weight of the newest measurement
  double fixedMs = 0, perPixelMs = 0, scale = 1;

  void calibrate(long long smallPx, double smallMs, long long fullPx, double fullMs) {
    perPixelMs = fullPx > smallPx ? (fullMs - smallMs) / static_cast<double>(fullPx - smallPx) : 0;
    if (!(perPixelMs > 0)) perPixelMs = fullMs / static_cast<double>(std::max(1LL, fullPx));
    fixedMs = std::max(0.0, smallMs - perPixelMs * static_cast<double>(smallPx));
  }
  double predict(long long px) const {
    return scale * (fixedMs + perPixelMs * static_cast<double>(px)) * (1 + kMargin);
  }
  // The most pixels whose estimate fits in `ms` (0: not even an empty render).
  long long maxPixels(double ms) const {
    const double base = ms / (scale * (1 + kMargin)) - fixedMs;
    if (!(base > 0)) return 0;
    if (!(perPixelMs > 0)) return LLONG_MAX;
    return static_cast<long long>(std::min(base / perPixelMs, 1e15));
  }
  void update(long long px, double ms) {
    const double base = fixedMs + perPixelMs * static_cast<double>(px);
    if (base > 0 && std::isfinite(ms)) scale = (1 - kAlpha) * scale + kAlpha * (ms / base);
  }
};

}  // namespace

Result<WalkResult> runWalk(const scenes::Scene& scene, const std::string& sceneLabel,
                           const scenes::CameraPath& path, const WalkOptions& opt) {
  const int frames = opt.maxFrames > 0 ? std::min(opt.maxFrames, path.frames) : path.frames;
  const bool writing = !opt.outDir.empty();
  if (writing) {
    HW_TRY(ensureWritableDir(opt.outDir));
    if (opt.saveFrames) {
      HW_TRY(ensureWritableDir(opt.outDir + "/frames"));
      HW_TRY(ensureWritableDir(opt.outDir + "/holes"));
    }
  }
  keyframe::RenderOptions ropt;
  ropt.depthMode = opt.depthMode;
  ropt.keyframeExcludeNear = opt.nearDistance;
  auto rendererR = keyframe::GeometryRenderer::create(scene, ropt);
  if (!rendererR) return rendererR.error();
  auto& renderer = **rendererR;
  // The reference uses the same renderer settings: the geometry image at the
  // same camera (DESIGN.md "What is measured").
  warp::WarpOptions wopt = opt.warp;
  // Only the depth merge and the near-object composition read the layers' eye z.
  wopt.writeEyeZ = opt.compose.mode == gapfill::ComposeMode::DepthMerge || opt.nearDistance > 0;
  // The large-leaf mask only feeds psnr_large_quads: without a reference it is not made.
  wopt.markLargeQuads = wopt.markLargeQuads && opt.reference;
  auto warperR = warp::Warper::create(wopt);
  if (!warperR) return warperR.error();
  auto& warper = **warperR;

  keyframe::KeyframeSchedule schedule{frames, path.keyframeEvery, {}};
  // Every frame's camera once (CameraPath::cameraAt rebuilds its arc-length
  // table per call); read-only, so the keyframe worker thread may use it too.
  const std::vector<Camera> cams = path.cameras();
  auto cameraOf = [&cams](int i) { return cams[static_cast<std::size_t>(i)]; };
  for (int k : opt.keyframeFrames)
    if (k > 0 && k < frames - 1) schedule.explicitFrames.push_back(k);
  std::sort(schedule.explicitFrames.begin(), schedule.explicitFrames.end());
  schedule.explicitFrames.erase(
      std::unique(schedule.explicitFrames.begin(), schedule.explicitFrames.end()),
      schedule.explicitFrames.end());
  if (!opt.keyframeFrames.empty() && schedule.explicitFrames.empty())
    schedule.explicitFrames.push_back(frames - 1);  // only the two ends
  // onlySegments: the frames walked.
  std::vector<char> walked;
  if (!opt.onlySegments.empty()) {
    walked.assign(static_cast<std::size_t>(frames), 0);
    for (const auto& [a, b] : opt.onlySegments) {
      if (a < 0 || b >= frames || a >= b || !schedule.isKeyframe(a) || !schedule.isKeyframe(b) ||
          schedule.bracket(a + 1).second != b)
        return makeError("walk: a segment to walk (" + std::to_string(a) + ", " +
                         std::to_string(b) +
                         ") is not two consecutive keyframes of the schedule within 0.." +
                         std::to_string(frames - 1));
      for (int i = a; i <= b; ++i) walked[static_cast<std::size_t>(i)] = 1;
    }
  }
  // Keyframe acquisition: cache (memory bound), and with asyncKeyframes a
  // worker that renders and meshes them ahead along the schedule. The worker
  // is declared first so it outlives the cache and is joined on every return.
  const keyframe::MeshSpec meshSpec{opt.mesh, opt.lod, opt.tileSize};
  const bool asyncKf = opt.asyncKeyframes && !opt.keyframeSource;
  std::unique_ptr<keyframe::AsyncKeyframes> kfWorker;
  if (asyncKf) {
    keyframe::AsyncKeyframeOptions aopt;
    aopt.render = ropt;
    aopt.mesh = meshSpec;
    aopt.maxQueued = std::max(1, opt.keyframePrefetch) + 2;  // the bracket + those ahead
    aopt.flushEveryTriangles = opt.keyframeFlushTriangles;
    aopt.workerNice = opt.keyframeWorkerNice;
    if (opt.keyframePacing == WalkOptions::KeyframePacing::Steps)
      aopt.stepsPerFrame = opt.keyframeStepsPerFrame;
    if (opt.keyframePacing == WalkOptions::KeyframePacing::Time ||
        opt.keyframePacing == WalkOptions::KeyframePacing::Slices) {
      aopt.slices = opt.keyframePacing == WalkOptions::KeyframePacing::Slices;
      const std::size_t nk = schedule.keyframes().size();
      aopt.framesPerKeyframe = nk > 1 ? static_cast<double>(frames - 1) / static_cast<double>(nk - 1) : 1.0;
      aopt.budgetScale = opt.keyframeBudgetScale;
    }
    auto w = keyframe::AsyncKeyframes::create(scene, cameraOf,
                                              aopt);
    if (!w) return w.error();
    kfWorker = std::move(*w);
  }
  keyframe::KeyframeCache cache(renderer, meshSpec, cameraOf,
                                keyframe::CacheOptions{opt.keyframeCacheBytes,
                                                       std::max(0, opt.keyframePrefetch)});
  cache.setSchedule(schedule);
  if (opt.keyframeSource) cache.setSource(opt.keyframeSource);
  if (kfWorker) cache.setProducer(kfWorker.get());
  double frameWaitMs = 0;  // this frame's wait for keyframes not ready
  // Warm-up, as a viewer loads before its first frame: the first two
  // keyframes are built (or, async, waited for) before the walk starts.
  Stopwatch warmupSw;
  if (asyncKf) HW_TRY(cache.prefetch(frames > 1 ? 1 : 0));
  for (int k : {schedule.bracket(0).first, schedule.bracket(frames > 1 ? 1 : 0).second}) {
    auto kf = cache.get(k);
    if (!kf) return kf.error();
  }
  const double warmupMs = warmupSw.ms();
  const int warmupStalls = cache.stalls();
  // Frame budget (WalkOptions::frameBudgetMs): the refresh render's cost model
  // is calibrated here, before the first frame (two scissored renders, each
  // timed on its second run: a tile at the centre and the whole image).
  const bool budgetOn = opt.frameBudgetMs > 0 || opt.frameBudgetAuto;
  if (opt.frameBudgetAuto &&
      (opt.frameBudgetWindow < 1 || !(opt.frameBudgetQuantile > 0 && opt.frameBudgetQuantile <= 1)))
    return makeError("walk: automatic frame budget: expected window >= 1 and 0 < quantile <= 1, "
                     "got window " + std::to_string(opt.frameBudgetWindow) + ", quantile " +
                     std::to_string(opt.frameBudgetQuantile));
  AutoFrameBudget autoBudget(std::max(1, opt.frameBudgetWindow),
                             opt.frameBudgetQuantile > 0 && opt.frameBudgetQuantile <= 1
                                 ? opt.frameBudgetQuantile
                                 : 0.9);
  // This frame's budget, ms (0 = none: no refresh, no pacing).
  double budgetMs = opt.frameBudgetAuto ? 0.0 : opt.frameBudgetMs;
  const bool trackAge = budgetOn || opt.pixelAge;
  constexpr int kTile = WalkOptions::kRefreshTilePx;
  RefreshCostModel refreshCost;
  double refreshCalibrationMs = 0;
  Image<Rgba8> refreshColour;
  if (budgetOn) {
    if (opt.staleAfter < 1)
      return makeError("walk: staleAfter " + std::to_string(opt.staleAfter) +
                       ": expected at least 1 frame");
    Stopwatch cal;
    const Camera cam0 = path.cameraAt(0);
    const int tw = std::min(kTile, cam0.width), th = std::min(kTile, cam0.height);
    const keyframe::PixelRect small{(cam0.width - tw) / 2, (cam0.height - th) / 2,
                                    (cam0.width - tw) / 2 + tw, (cam0.height - th) / 2 + th};
    const keyframe::PixelRect full{0, 0, cam0.width, cam0.height};
    double t[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      const keyframe::PixelRect& r = k == 0 ? small : full;
      for (int rep = 0; rep < 2; ++rep) {
        Stopwatch sw;
        HW_TRY(renderer.renderColourRect(cam0, r, refreshColour));
        t[k] = sw.ms();
      }
    }
    refreshCost.calibrate(small.area(), t[0], full.area(), t[1]);
    refreshCalibrationMs = cal.ms();
  }
  std::vector<std::uint32_t> tileScores;
  std::vector<int> tileOrder;
  std::vector<double> stalePixels, maxAges, refreshedPixels, refreshMs, frameIntervalMs,
      inBetweenIntervalMs;
  int framesRefreshed = 0, budgetOverruns = 0, budgetOverrunsInBetween = 0,
      budgetOverrunsByRefresh = 0;
  double workBeforeRefreshMs = -1;  // this frame's work when a refresh started (-1: none)
  std::vector<double> refreshPredictedOverMeasured;
  long long refreshRectsTotal = 0;
  std::vector<double> frameMsAll, inBetweenFrameMs, stallMs;
  std::map<int, std::unique_ptr<warp::WarpSource>> sources;  // keyframe → GPU copy
  std::map<int, warp::WarpStats> uploadStats;

  warp::Layer layerA, layerB;
  gapfill::Frame frame, previous;
  bool havePrevious = false;
  Image<Rgba8> reference;
  // Per-frame entries: kept as JSON for callers that read them, otherwise
  // streamed to a scratch file beside the report, so a 10,000-frame walk's
  // memory stays flat (about 3 KiB per frame as JSON objects).
  json framesJson = json::array();
  std::vector<double> speedup;
  const std::string framesScratch =
      writing ? opt.outDir + "/.report-frames.tmp-" + std::to_string(::getpid()) : std::string();
  std::FILE* framesFile = nullptr;
  struct ScratchGuard {
    std::FILE*& f;
    const std::string& path;
    ~ScratchGuard() {
      if (f) std::fclose(f);
      if (!path.empty()) std::remove(path.c_str());
    }
  } scratchGuard{framesFile, framesScratch};
  std::unique_ptr<TemporaryFile> scratchRegistration;  // removes a named scratch on SIGINT/SIGTERM
  if (writing && !opt.keepFrames) {
    // Unnamed (O_TMPFILE) where the file system allows: nothing is left even after SIGKILL.
    std::string named;
    framesFile = openScratchFile(opt.outDir, framesScratch.substr(opt.outDir.size() + 1), &named);
    if (!named.empty()) scratchRegistration = std::make_unique<TemporaryFile>(named);
    if (!framesFile) return makeError("cannot write " + framesScratch + ": " + std::strerror(errno));
  }
  bool firstFrameWritten = false;
  int backgroundSkips = 0, previousSkips = 0;
  std::vector<double> drawnQuads, subdividedQuads, pointsPerKeyframe;  // per keyframe, after subdivision
  std::vector<double> foregroundUncovered;  // pixels the foreground layer left empty
  std::vector<double> bgCulled;  // background quads left out per frame (cullBackground)
  std::vector<double> psnrs, ssims, holesBefore, holesAfter, inBetweenMs, referenceMs,
      keyframeMs, quadsPerKeyframe, warpMs, composeMs, lodBuildMs, onePixelLeaves;
  // Pixels drawn from large leaves (warp::Layer::largeQuad), per I frame.
  std::vector<double> psnrLargeQuads, largeQuadPixels;
  // Forgets that pixel p came from a large leaf (a near object or refresh drew it).
  auto notLargeQuad = [&layerA, &layerB](std::size_t p) {
    for (warp::Layer* l : {&layerA, &layerB})
      if (p < l->largeQuad.size()) l->largeQuad.data()[p] = 0;
  };
  Progress progress(opt.progress, frames, "walk");
  long long glErrors = 0;  // glGetError at each frame's end; plus KHR_debug when installed
  const long long debugErrors0 = gl::debugCallbackErrors();
  json rssKiB = json::array();  // [frame, KiB] after every 500th frame (scripts/soak.sh)

  // Strip frames: spread over the in-between frames.
  std::vector<int> inBetween;
  for (int i = 0; i < frames; ++i)
    if (!schedule.isKeyframe(i)) inBetween.push_back(i);
  std::vector<int> stripFrames;
  for (int s = 0; s < opt.strips && !inBetween.empty(); ++s) {
    const std::size_t k = (2 * s + 1) * inBetween.size() / (2 * static_cast<std::size_t>(opt.strips));
    if (stripFrames.empty() || stripFrames.back() != inBetween[k]) stripFrames.push_back(inBetween[k]);
  }
  std::vector<Image<Rgba8>> strips;
  std::vector<json> stripInfo;

  auto getSource = [&](int k, const keyframe::CachedKeyframe** kfOut) -> Status {
    auto kf = cache.get(k);
    if (!kf) return kf.error();
    *kfOut = *kf;
    if (cache.lastWaitMs() > 0) {
      frameWaitMs += cache.lastWaitMs();
      stallMs.push_back(cache.lastWaitMs());
    }
    if (!sources.count(k)) {
      warp::WarpStats ws;
      auto src = warper.upload((*kf)->keyframe, (*kf)->mesh, &ws);
      if (!src) return src.error();
      sources[k] = std::move(*src);
      uploadStats[k] = ws;
      keyframeMs.push_back((*kf)->renderMs + (*kf)->mesh.stats.deltaMs +
                           (*kf)->mesh.stats.subdivideMs + (*kf)->mesh.stats.cornersMs + ws.uploadMs);
      quadsPerKeyframe.push_back(static_cast<double>((*kf)->mesh.stats.quads));
      drawnQuads.push_back(ws.drawnQuads);
      pointsPerKeyframe.push_back(ws.points);
      subdividedQuads.push_back(ws.subdividedQuads);
      const auto& ms = (*kf)->mesh.stats;
      lodBuildMs.push_back(ms.deltaMs + ms.subdivideMs + ms.cornersMs);
      onePixelLeaves.push_back(static_cast<double>(ms.onePixelLeaves));
    }
    return {};
  };

  // Near objects: drawn by the geometry renderer at `cam` and put in front of
  // `frame` wherever they are nearer than `behindZ` (0 or kSkyEyeZ = nothing
  // there). Holes they cover stop being holes.
  Image<Rgba8> nearColour;
  Image<float> nearEyeZ;
  Image<std::uint8_t> nearCovered;
  std::vector<double> nearMs;
  auto drawNear = [&](const Camera& cam, int k0, int k1, const Image<float>& behindZ,
                      json& ms) -> Status {
    const glm::dvec3 eyes[2] = {cameraOf(k0).eye, cameraOf(k1).eye};
    keyframe::RenderStats rs;
    Stopwatch sw;
    HW_TRY(renderer.renderNear(cam, eyes, k0 == k1 ? 1 : 2, opt.nearDistance, nearColour, nearEyeZ,
                               nearCovered, &rs));
    const std::size_t n = nearColour.size();
    const bool haveZ = behindZ.size() == n;
    int holes = 0, unfilled = 0;
    for (std::size_t p = 0; p < n; ++p) {
      if (nearCovered.data()[p]) {
        const float z = haveZ ? behindZ.data()[p] : 0.0f;
        const bool empty = frame.holesBefore.data()[p] != 0 || z <= 0.0f;
        if (empty || nearEyeZ.data()[p] < z) {
          notLargeQuad(p);
          frame.colour.data()[p] = nearColour.data()[p];
          frame.holesBefore.data()[p] = 0;
          frame.valid.data()[p] = 1;
        }
      }
      holes += frame.holesBefore.data()[p];
      unfilled += frame.valid.data()[p] == 0;
    }
    frame.holeFractionBefore = n ? double(holes) / double(n) : 0.0;
    frame.holeFractionAfter = n ? double(unfilled) / double(n) : 0.0;
    const double t = sw.ms();
    ms["near_geometry"] = t;
    ms["near_geometry_draw"] = rs.drawMs;
    nearMs.push_back(t);
    return {};
  };

  // The end of a frame's work: ms["frame"] (work), then with a budget and
  // pacing a sleep until the budget has passed since the frame started, and
  // ms["interval"], the presented frame interval (work + that wait; the
  // reference render and the metrics stay outside both).
  Stopwatch frameSw;
  std::chrono::steady_clock::time_point frameStart;
  std::vector<double> sliceMs;  // keyframe slices run at the end of each frame (Slices pacing)
  // frame_times.png: work and presented interval per frame, keyframe frames
  // apart, and each frame's budget (plotBudget.y also gives the summary's
  // per-frame budget stats).
  int currentFrame = 0;
  Series plotWork{"in-between work (ms.frame)"}, plotKeyWork{"keyframe frame work"},
      plotInterval{"presented interval (ms.interval)"}, plotBudget{"budget"};
  for (Series* p : {&plotWork, &plotKeyWork, &plotInterval, &plotBudget}) {  // no growth per frame
    p->x.reserve(static_cast<std::size_t>(frames));
    p->y.reserve(static_cast<std::size_t>(frames));
  }
  auto endFrameWork = [&](json& ms, bool keyframeFrame) {
    if (kfWorker && opt.keyframePacing == WalkOptions::KeyframePacing::Slices) {
      const double slice = kfWorker->runSlice();  // part of the frame: the CPUs are the worker's now
      ms["keyframe_slice"] = slice;
      sliceMs.push_back(slice);
    }
    const double work = frameSw.ms();
    ms["frame"] = work;
    if (kfWorker) ms["keyframe_worker"] = kfWorker->workerMsSinceTick();
    if (budgetOn && budgetMs > 0) {
      if (work > budgetMs) {
        ++budgetOverruns;
        budgetOverrunsInBetween += !keyframeFrame;
        // Within the budget before a refresh, over it after: the estimate missed.
        budgetOverrunsByRefresh += workBeforeRefreshMs >= 0 && workBeforeRefreshMs <= budgetMs;
      }
      if (opt.paceFrames)
        std::this_thread::sleep_until(
            frameStart + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double, std::milli>(budgetMs)));
    }
    const double interval =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart)
            .count();
    ms["pacing_wait"] = std::max(0.0, interval - work);
    ms["interval"] = interval;
    frameIntervalMs.push_back(interval);
    Series& w = keyframeFrame ? plotKeyWork : plotWork;
    w.x.push_back(currentFrame);
    w.y.push_back(work);
    plotInterval.x.push_back(currentFrame);
    plotInterval.y.push_back(interval);
    if (budgetOn && budgetMs > 0) {
      plotBudget.x.push_back(currentFrame);
      plotBudget.y.push_back(budgetMs);
    }
    if (!keyframeFrame) inBetweenIntervalMs.push_back(interval);
  };

  for (int i = 0; i < frames; ++i) {
    if (!walked.empty() && !walked[static_cast<std::size_t>(i)]) continue;
    currentFrame = i;
    const Camera& cam = cams[static_cast<std::size_t>(i)];
    json fj;
    fj["index"] = i;
    const auto [k0, k1] = schedule.bracket(i);
    json ms = json::object();
    double refMs = std::nan("");
    if (opt.reference) {
      keyframe::RenderStats rs;
      HW_TRY(renderer.renderColour(cam, reference, &rs));
      refMs = rs.drawMs + rs.readbackMs;
      referenceMs.push_back(refMs);
    }
    // What a viewer waits for: keyframe acquisition (build or wait),
    // upload, warp, compose; not the reference or the metrics.
    if (opt.frameBudgetAuto) {
      budgetMs = autoBudget.budgetMs();
      fj["budget_ms"] = budgetMs > 0 ? json(budgetMs) : json(nullptr);
    }
    frameSw.restart();
    frameStart = std::chrono::steady_clock::now();
    workBeforeRefreshMs = -1;
    frameWaitMs = 0;
    if (asyncKf) {
      kfWorker->frameTick();
      HW_TRY(cache.prefetch(i));
    }
    if (k0 == k1) {
      // Keyframe: the geometry frame itself is displayed.
      const keyframe::CachedKeyframe* kf = nullptr;
      HW_TRY(getSource(k0, &kf));
      fj["is_keyframe"] = true;
      fj["keyframes"] = {k0};
      fj["quads"] = kf->mesh.stats.quads;
      const auto& st = kf->mesh.stats;
      ms = {{"keyframe_render", kf->renderMs}, {"delta", st.deltaMs},
            {"subdivide", st.subdivideMs},     {"corners", st.cornersMs},
            {"upload", uploadStats[k0].uploadMs}};
      ms["total"] = kf->renderMs + st.deltaMs + st.subdivideMs + st.cornersMs + uploadStats[k0].uploadMs;
      const Image<Rgba8>& shown = kf->keyframe.colour;
      if (frame.colour.width() != cam.width || frame.colour.height() != cam.height) {
        frame.colour.resize(cam.width, cam.height);
        frame.holesBefore.resize(cam.width, cam.height);
        frame.valid.resize(cam.width, cam.height);
      }
      frame.colour = shown;
      frame.holesBefore.fill(0);
      frame.valid.fill(1);
      frame.holeFractionBefore = frame.holeFractionAfter = 0;
      if (opt.nearDistance > 0) {
        HW_TRY(drawNear(cam, k0, k0, kf->keyframe.eyeZ, ms));
        ms["total"] = ms["total"].get<double>() + ms["near_geometry"].get<double>();
      }
      // The displayed keyframe costs no warp: upload the next keyframe now
      // if it is already built, instead of on the next frame.
      if (i + 1 < frames) {
        const int next = schedule.bracket(i + 1).second;
        if (next != k0 && !sources.count(next) && cache.contains(next)) {
          const keyframe::CachedKeyframe* kn = nullptr;
          HW_TRY(getSource(next, &kn));
          // llvmpipe's first draw from a new source costs about a warp more
          // than later ones (measured): take it here, into a scratch layer.
          HW_TRY(warper.warp(*sources[next], cam, layerB, nullptr));
        }
      }
      if (trackAge) {
        Stopwatch sa;
        const gapfill::AgeStats as = gapfill::updateAge(havePrevious ? &previous : nullptr, frame);
        ms["age"] = sa.ms();
        fj["stale_pixels"] = as.stale;
        fj["max_age"] = as.maxAge;
      }
      endFrameWork(ms, true);
      fj["holes_before_fallback"] = 0.0;
      fj["holes_after_fallback"] = 0.0;
      if (opt.reference) {
        fj["psnr"] = finiteOrNull(psnr(frame.colour, reference));  // identical: +inf → null
        fj["ssim"] = ssim(frame.colour, reference);
      } else {
        fj["psnr"] = nullptr;
        fj["ssim"] = nullptr;
      }
    } else {
      const keyframe::CachedKeyframe* kfa = nullptr;
      const keyframe::CachedKeyframe* kfb = nullptr;
      HW_TRY(getSource(k0, &kfa));
      HW_TRY(getSource(k1, &kfb));
      // The keyframe whose eye is nearer is the foreground (paper §2.2 (i)).
      const int fgPick = gapfill::chooseForeground(cam.eye, kfa->keyframe.camera.eye,
                                                   kfb->keyframe.camera.eye);
      const int fgFrame = fgPick == 0 ? k0 : k1, bgFrame = fgPick == 0 ? k1 : k0;
      Stopwatch total;
      const bool fused = opt.fusedLayers && opt.compose.mode == gapfill::ComposeMode::Overlay;
      bool bgSkipped = false, prevSkipped = false;
      int fgUncovered = 0;
      int quadsDrawn = 0;
      double composeT = 0;
      if (fused) {
        warp::PairStats ps;
        HW_TRY(warper.warpPair(*sources[fgFrame], sources[bgFrame].get(), cam, layerA,
                               opt.skipBackground, &ps));
        bgSkipped = !ps.backgroundDrawn;
        fgUncovered = ps.uncoveredByForeground;
        Stopwatch sc;
        if (ps.uncovered == 0 && opt.skipPrevious) {
          // Nothing to fill: the layer image is the frame (buffers swapped, no copy).
          prevSkipped = true;
          if (frame.colour.width() != cam.width || frame.colour.height() != cam.height) {
            frame.holesBefore.resize(cam.width, cam.height);
            frame.valid.resize(cam.width, cam.height);
          }
          std::swap(frame.colour, layerA.colour);
          frame.holesBefore.fill(0);
          frame.valid.fill(1);
          frame.holeFractionBefore = frame.holeFractionAfter = 0;
          frame.fromForeground = cam.width * cam.height - ps.fromBackground;
          frame.fromBackground = ps.fromBackground;
          frame.fromPrevious = frame.unfilled = 0;
        } else {
          gapfill::compose(layerA, nullptr, havePrevious ? &previous : nullptr, opt.compose, frame);
          frame.fromForeground -= ps.fromBackground;
          frame.fromBackground = ps.fromBackground;
        }
        composeT = sc.ms();
        quadsDrawn = ps.quadsForeground + ps.quadsBackground;
        if (ps.backgroundDrawn) bgCulled.push_back(ps.backgroundCulled);
        ms = {{"warp_a", ps.foregroundMs}, {"warp_b", ps.backgroundMs},
              {"readback", ps.readbackMs}, {"compose", composeT}};
        if (ps.cullMs > 0) ms["cull"] = ps.cullMs;
        warpMs.push_back(ps.foregroundMs + ps.backgroundMs + ps.readbackMs);
      } else {
        warp::WarpStats wa, wb;
        HW_TRY(warper.warp(*sources[fgFrame], cam, layerA, &wa));
        bgSkipped = opt.skipBackground && wa.uncovered == 0;
        fgUncovered = wa.uncovered;
        if (!bgSkipped) HW_TRY(warper.warp(*sources[bgFrame], cam, layerB, &wb));
        Stopwatch sc;
        gapfill::compose(layerA, bgSkipped ? nullptr : &layerB,
                         havePrevious ? &previous : nullptr, opt.compose, frame);
        composeT = sc.ms();
        quadsDrawn = wa.quads + wb.quads;
        ms = {{"warp_a", wa.drawMs + wa.readbackMs}, {"warp_b", wb.drawMs + wb.readbackMs},
              {"warp_a_draw", wa.drawMs},           {"warp_b_draw", wb.drawMs},
              {"readback", wa.readbackMs + wb.readbackMs},
              {"compose", composeT}};
        warpMs.push_back(wa.drawMs + wa.readbackMs + wb.drawMs + wb.readbackMs);
      }
      if (opt.nearDistance > 0) {
        // The layers' eye z: the composed one (fused) or the foreground's where it
        // covers, else the background's (separate).
        if (!fused && layerB.eyeZ.size() == layerA.eyeZ.size() && !bgSkipped) {
          for (std::size_t p = 0; p < layerA.eyeZ.size(); ++p)
            if (!layerA.coverage.data()[p]) layerA.eyeZ.data()[p] = layerB.eyeZ.data()[p];
        }
        HW_TRY(drawNear(cam, k0, k1, layerA.eyeZ, ms));
      }
      const double totalMs = total.ms();
      ms["total"] = totalMs;
      if (trackAge) {
        // Age (gapfill/age.h), then with a budget the refresh of the oldest
        // region while its estimated cost fits in the time left.
        Stopwatch sa;
        gapfill::AgeStats as = gapfill::updateAge(havePrevious ? &previous : nullptr, frame);
        ms["age"] = sa.ms();
        fj["stale_pixels_before_refresh"] = as.stale;
        if (budgetOn) {
          Stopwatch sr;
          int cols = 0, rows = 0;
          gapfill::scoreStaleTiles(frame.age, opt.staleAfter, kTile, tileScores, &cols, &rows);
          long long refreshed = 0;
          json rects = json::array();
          for (int n = 0; n < WalkOptions::kMaxRefreshRects; ++n) {
            if (budgetMs <= 0) break;
            const long long maxPx = refreshCost.maxPixels(budgetMs - frameSw.ms());
            keyframe::PixelRect r;
            if (maxPx < 1 || !gapfill::chooseRefreshRect(tileScores, cols, rows, kTile, cam.width,
                                                        cam.height, maxPx, tileOrder, &r))
              break;
            const double predicted = refreshCost.predict(r.area());
            if (workBeforeRefreshMs < 0) workBeforeRefreshMs = frameSw.ms();
            Stopwatch one;
            HW_TRY(renderer.renderColourRect(cam, r, refreshColour));
            gapfill::applyRefresh(r, refreshColour, frame);
            for (int y = r.y0; y < r.y1; ++y)
              for (int x = r.x0; x < r.x1; ++x)
                notLargeQuad(static_cast<std::size_t>(y) * static_cast<std::size_t>(cam.width) +
                             static_cast<std::size_t>(x));
            const double t = one.ms();
            refreshCost.update(r.area(), t);
            refreshPredictedOverMeasured.push_back(t > 0 ? predicted / t : std::nan(""));
            gapfill::clearTileScores(r, cols, kTile, tileScores);
            refreshed += r.area();
            rects.push_back({{"rect", {r.x0, r.y0, r.width(), r.height()}},
                             {"ms", t},
                             {"predicted_ms", predicted}});
          }
          if (refreshed > 0) {
            as = gapfill::ageStats(frame.age);
            ++framesRefreshed;
            refreshRectsTotal += static_cast<long long>(rects.size());
          }
          const double rt = sr.ms();
          ms["refresh"] = rt;
          refreshMs.push_back(rt);
          refreshedPixels.push_back(static_cast<double>(refreshed));
          fj["refreshed_pixels"] = refreshed;
          fj["refresh_rects"] = std::move(rects);
        }
        fj["stale_pixels"] = as.stale;
        fj["max_age"] = as.maxAge;
        stalePixels.push_back(as.stale);
        maxAges.push_back(as.maxAge);
      }
      backgroundSkips += bgSkipped;
      previousSkips += prevSkipped;
      fj["is_keyframe"] = false;
      fj["keyframes"] = {k0, k1};
      fj["foreground"] = fgFrame;
      fj["quads"] = quadsDrawn;
      fj["skipped"] = {{"background", bgSkipped}, {"previous_frame", prevSkipped}};
      fj["foreground_uncovered_pixels"] = fgUncovered;
      foregroundUncovered.push_back(fgUncovered);
      endFrameWork(ms, false);
      inBetweenFrameMs.push_back(ms["frame"].get<double>());
      if (opt.frameBudgetAuto)  // the next frames' budget: this frame's work without its refresh
        autoBudget.add(ms["frame"].get<double>() - (ms.contains("refresh") ? ms["refresh"].get<double>() : 0.0));
      fj["holes_before_fallback"] = frame.holeFractionBefore;
      fj["holes_after_fallback"] = frame.holeFractionAfter;
      holesBefore.push_back(frame.holeFractionBefore);
      holesAfter.push_back(frame.holeFractionAfter);
      inBetweenMs.push_back(totalMs);
      composeMs.push_back(composeT);
      if (opt.reference) {
        const double p = psnr(frame.colour, reference);
        const double s = ssim(frame.colour, reference);
        const ChannelMse m = channelMse(frame.colour, reference);
        fj["psnr"] = finiteOrNull(p);
        fj["ssim"] = s;
        fj["mse"] = {{"r", m.r}, {"g", m.g}, {"b", m.b}};
        psnrs.push_back(std::isfinite(p) ? p : 99.0);
        ssims.push_back(s);
      } else {
        fj["psnr"] = nullptr;
        fj["ssim"] = nullptr;
      }
      // Pixels whose colour came from a large leaf of either layer (the ones
      // subdivision changes; previous-frame fill, near objects, refresh: not).
      // Unknown with the depth merge, which does not say which layer won.
      if (wopt.markLargeQuads && (fused || opt.compose.mode == gapfill::ComposeMode::Overlay)) {
        Image<std::uint8_t>& large = layerA.largeQuad;
        if (!fused && !bgSkipped)
          for (std::size_t p = 0; p < large.size(); ++p)
            if (!layerA.coverage.data()[p])
              large.data()[p] = layerB.coverage.data()[p] ? layerB.largeQuad.data()[p] : 0;
        long long count = 0;
        for (std::size_t p = 0; p < large.size(); ++p) count += large.data()[p];
        fj["large_quad_pixels"] = count;
        largeQuadPixels.push_back(static_cast<double>(count));
        const double pl = opt.reference ? psnrCapped(frame.colour, reference, large) : std::nan("");
        fj["psnr_large_quads"] = finiteOrNull(pl);  // NaN: no such pixel or no reference
        if (std::isfinite(pl)) psnrLargeQuads.push_back(pl);
      } else {
        fj["large_quad_pixels"] = nullptr;
        fj["psnr_large_quads"] = nullptr;
      }
      if (writing && opt.reference &&
          std::find(stripFrames.begin(), stripFrames.end(), i) != stripFrames.end()) {
        const Image<Rgba8> diff = diffImage(frame.colour, reference, 4);
        const Image<Rgba8> holes = maskToImage(frame.holesBefore, Rgba8{255, 40, 40, 255},
                                               Rgba8{30, 30, 30, 255});
        strips.push_back(hstack({&reference, &frame.colour, &diff, &holes}, 4,
                                Rgba8{255, 255, 255, 255}));
        stripInfo.push_back({{"frame", i}, {"psnr", fj["psnr"]}, {"ssim", fj["ssim"]},
                             {"holes_before_fallback", frame.holeFractionBefore}});
      }
    }
    ms["keyframe_wait"] = frameWaitMs;
    frameMsAll.push_back(ms["frame"].get<double>());
    fj["reference_ms"] = opt.reference ? json(refMs) : json(nullptr);
    fj["ms"] = ms;
    if (writing && opt.saveFrames) {
      HW_TRY(writePng(opt.outDir + "/frames/" + frameName(i), frame.colour));
      HW_TRY(writePng(opt.outDir + "/holes/" + frameName(i),
                      maskToImage(frame.holesBefore, Rgba8{255, 40, 40, 255}, Rgba8{0, 0, 0, 255})));
    }
    if (!fj["is_keyframe"].get<bool>() && fj["reference_ms"].is_number())
      speedup.push_back(fj["reference_ms"].get<double>() / fj["ms"]["total"].get<double>());
    if (opt.keepFrames) {
      framesJson.push_back(std::move(fj));
    } else if (framesFile) {
      const std::string text = (firstFrameWritten ? ",\n" : "\n") + fj.dump();
      firstFrameWritten = true;
      if (std::fwrite(text.data(), 1, text.size(), framesFile) != text.size())
        return makeError("cannot write " + framesScratch + ": " + std::strerror(errno));
    }
    std::swap(previous, frame);
    havePrevious = true;
    // Drop GPU copies of keyframes no later frame can use.
    for (auto it = sources.begin(); it != sources.end();)
      it = it->first < k0 ? sources.erase(it) : std::next(it);
    for (auto it = uploadStats.begin(); it != uploadStats.end();)
      it = it->first < k0 ? uploadStats.erase(it) : std::next(it);
    cache.releaseBefore(k0);
    glErrors += gl::drainGlErrors();
    if ((i + 1) % 500 == 0) rssKiB.push_back({i + 1, residentKiB()});
    progress.update(i + 1);
  }

  json summary;
  summary["scene"] = {{"name", sceneLabel}, {"triangles", scene.triangleCount()}};
  summary["resolution"] = {path.width, path.height};
  summary["frames"] = frames;
  summary["keyframes"] = static_cast<int>(cache.builds());
  summary["in_between_frames"] = static_cast<int>(inBetween.size());
  summary["keyframe_every"] = path.keyframeEvery;
  summary["keyframe_schedule"] = opt.keyframeFrames.empty() ? "fixed" : "explicit";
  summary["keyframe_frames"] = schedule.keyframes();
  summary["tau"] = opt.lod.tauParallaxPx > 0 ? json(nullptr) : json(opt.lod.tau);
  summary["tau_parallax_px"] = opt.lod.tauParallaxPx;
  summary["criterion"] = keyframe::deltaCriterionName(opt.lod.criterion);
  summary["mesh"] = keyframe::meshMethodName(opt.mesh);
  summary["planarity"] = keyframe::planarityName(opt.lod.planarity);
  summary["merge_strips"] = opt.lod.mergeStrips;
  summary["tau_gradient"] = opt.lod.tauGradient;
  summary["tile_size"] = opt.mesh == keyframe::MeshMethod::UniformTiles ? json(opt.tileSize) : json(nullptr);
  summary["depth_mode"] = depthModeName(opt.depthMode);
  summary["compose_mode"] = gapfill::composeModeName(opt.compose.mode);
  summary["texcoords"] = warp::texcoordModeName(opt.warp.texcoords);
  summary["sky_backdrop"] = opt.warp.skyBackdrop;
  const bool fusedUsed = opt.fusedLayers && opt.compose.mode == gapfill::ComposeMode::Overlay;
  summary["layers"] = fusedUsed ? "fused" : "separate";
  summary["near_distance"] = opt.nearDistance;
  summary["subdivision"] = warp::subdivisionName(opt.warp.subdivision);
  summary["primitives"] = warp::primitivesName(opt.warp.primitives);
  summary["points_per_keyframe"] = stats(pointsPerKeyframe);  // 1×1 leaves as points (--primitives points)
  summary["cull_background"] = opt.warp.cullBackground && opt.warp.primitives != warp::Primitives::Independent;
  summary["background_quads_culled"] = stats(bgCulled);
  summary["subdivide_cell_px"] = opt.warp.subdivideCellPx;
  summary["drawn_quads_per_keyframe"] = stats(drawnQuads);
  summary["subdivided_quads_per_keyframe"] = stats(subdividedQuads);
  summary["near_geometry_ms"] = stats(nearMs);
  summary["skip_background"] = opt.skipBackground;
  summary["skip_previous_frame"] = opt.skipPrevious;
  summary["background_layer_skipped_frames"] = backgroundSkips;
  summary["foreground_uncovered_pixels"] = stats(foregroundUncovered);
  summary["previous_frame_pass_skipped_frames"] = previousSkips;
  summary["psnr"] = stats(psnrs);
  summary["psnr_large_quads"] = stats(psnrLargeQuads);
  summary["large_quad_pixels"] = stats(largeQuadPixels);
  summary["ssim"] = stats(ssims);
  summary["holes_before_fallback"] = stats(holesBefore);
  summary["holes_after_fallback"] = stats(holesAfter);
  summary["quads_per_keyframe"] = stats(quadsPerKeyframe);
  summary["in_between_ms"] = stats(inBetweenMs);
  summary["warp_ms"] = stats(warpMs);
  summary["compose_ms"] = stats(composeMs);
  summary["reference_ms"] = stats(referenceMs);
  summary["keyframe_build_ms"] = stats(keyframeMs);
  summary["lod_build_ms"] = stats(lodBuildMs);
  summary["one_pixel_leaves_per_keyframe"] = stats(onePixelLeaves);
  summary["speedup_reference_over_in_between"] = stats(speedup);
  summary["gl_errors"] =
      std::max(glErrors, debugErrors0 < 0 ? 0LL : gl::debugCallbackErrors() - debugErrors0);
  summary["resident_kib_every_500_frames"] = rssKiB;
  // Frame-time stability (issue #8): wall time per frame as a viewer sees
  // it, keyframe frames included, and the in-between frames alone.
  auto ratio = [](const std::vector<double>& v) {
    const double m = median(v);
    return m > 0 ? finiteOrNull(percentile(v, 95) / m) : json(nullptr);
  };
  summary["keyframe_acquisition"] = opt.keyframeSource ? "source" : asyncKf ? "async" : "sync";
  summary["async_keyframes"] = asyncKf;
  summary["keyframe_prefetch"] = asyncKf ? json(opt.keyframePrefetch) : json(nullptr);
  summary["keyframe_cache_mb"] = static_cast<double>(opt.keyframeCacheBytes) / (1 << 20);
  summary["keyframe_cache_peak_mb"] = static_cast<double>(cache.peakBytes()) / (1 << 20);
  summary["keyframe_cache_evictions"] = cache.evictions();
  summary["keyframe_cache_released"] = cache.released();
  summary["frame_ms"] = stats(frameMsAll);
  summary["frame_ms_p95_over_median"] = ratio(frameMsAll);
  summary["in_between_frame_ms"] = stats(inBetweenFrameMs);
  summary["in_between_frame_ms_p95_over_median"] = ratio(inBetweenFrameMs);
  summary["keyframe_stalls"] = cache.stalls() - warmupStalls;
  summary["keyframe_warmup_ms"] = warmupMs;
  summary["keyframe_stall_ms"] = stats(stallMs);
  double stallTotal = 0;
  for (double t : stallMs) stallTotal += t;
  summary["keyframe_stall_ms_total"] = stallTotal;
  summary["keyframe_flush_triangles"] = asyncKf ? json(opt.keyframeFlushTriangles) : json(nullptr);
  summary["keyframe_worker_nice"] = asyncKf ? json(opt.keyframeWorkerNice) : json(nullptr);
  const char* pacingName = opt.keyframePacing == WalkOptions::KeyframePacing::Time     ? "time"
                           : opt.keyframePacing == WalkOptions::KeyframePacing::Slices ? "slices"
                           : opt.keyframePacing == WalkOptions::KeyframePacing::Steps  ? "steps"
                                                                                       : "none";
  summary["keyframe_pacing"] = asyncKf ? json(pacingName) : json(nullptr);
  summary["keyframe_budget_scale"] =
      asyncKf && (opt.keyframePacing == WalkOptions::KeyframePacing::Time ||
                  opt.keyframePacing == WalkOptions::KeyframePacing::Slices)
          ? json(opt.keyframeBudgetScale)
          : json(nullptr);
  summary["keyframe_slice_ms"] = sliceMs.empty() ? json(nullptr) : stats(sliceMs);
  summary["keyframe_steps_per_frame"] =
      asyncKf && opt.keyframePacing == WalkOptions::KeyframePacing::Steps ? json(opt.keyframeStepsPerFrame)
                                                                          : json(nullptr);
  summary["keyframe_worker_busy_ms"] = kfWorker ? json(kfWorker->workerBusyMs()) : json(nullptr);
  // Frame budget and pixel age (issue #8; WalkOptions::frameBudgetMs).
  // With the automatic budget: the median of the per-frame budgets.
  summary["frame_budget_ms"] =
      opt.frameBudgetAuto ? finiteOrNull(median(plotBudget.y)) : json(opt.frameBudgetMs);
  summary["frame_budget_mode"] = opt.frameBudgetAuto ? "auto" : budgetOn ? "fixed" : "off";
  summary["frame_budget_auto"] =
      opt.frameBudgetAuto ? json{{"quantile", opt.frameBudgetQuantile},
                                 {"window_frames", opt.frameBudgetWindow},
                                 {"budget_ms", stats(plotBudget.y)},
                                 {"frames_without_budget", frames - static_cast<int>(plotBudget.y.size())}}
                          : json(nullptr);
  summary["frame_pacing"] = budgetOn && opt.paceFrames;
  summary["pixel_age"] = trackAge;
  summary["stale_after"] = budgetOn ? json(opt.staleAfter) : json(nullptr);
  summary["refresh_tile_px"] = budgetOn ? json(kTile) : json(nullptr);
  summary["stale_pixels"] = stats(stalePixels);
  summary["max_age"] = stats(maxAges);
  summary["refreshed_pixels"] = stats(refreshedPixels);
  summary["refresh_ms"] = stats(refreshMs);
  summary["frames_refreshed"] = framesRefreshed;
  summary["refresh_rects"] = refreshRectsTotal;
  summary["refresh_cost_model"] =
      budgetOn ? json{{"fixed_ms", refreshCost.fixedMs},
                      {"per_megapixel_ms", refreshCost.perPixelMs * 1e6},
                      {"scale_at_end", refreshCost.scale},
                      {"margin", RefreshCostModel::kMargin},
                      {"calibration_ms", refreshCalibrationMs}}
               : json(nullptr);
  summary["frame_interval_ms"] = stats(frameIntervalMs);
  summary["frame_interval_ms_p95_over_median"] = ratio(frameIntervalMs);
  summary["in_between_frame_interval_ms"] = stats(inBetweenIntervalMs);
  summary["in_between_frame_interval_ms_p95_over_median"] = ratio(inBetweenIntervalMs);
  summary["budget_overruns"] = budgetOn ? json(budgetOverruns) : json(nullptr);
  summary["budget_overruns_in_between"] = budgetOn ? json(budgetOverrunsInBetween) : json(nullptr);
  summary["budget_overruns_by_refresh"] = budgetOn ? json(budgetOverrunsByRefresh) : json(nullptr);
  summary["refresh_predicted_over_measured"] = stats(refreshPredictedOverMeasured);
  summary["machine"] = machineInfo(opt.glRenderer, opt.glVersion);
  summary["strips"] = stripInfo;

  WalkResult result;
  result.report = {{"frames", framesJson}, {"summary", summary}};
  if (writing) {
    {
      PlotOptions po;
      char budgetLabel[64] = "";
      if (opt.frameBudgetAuto)
        std::snprintf(budgetLabel, sizeof budgetLabel, ", auto budget (p%g of %d frames)",
                      opt.frameBudgetQuantile * 100, opt.frameBudgetWindow);
      else if (budgetOn)
        std::snprintf(budgetLabel, sizeof budgetLabel, ", budget %.1f ms", opt.frameBudgetMs);
      po.title = "Frame times: " + sceneLabel + (asyncKf ? ", async keyframes" : "") + budgetLabel;
      po.xLabel = "frame";
      po.yLabel = "ms (log)";
      po.logY = true;
      po.width = 1000;
      po.height = 480;
      plotWork.markers = false;
      plotInterval.lines = false;
      plotInterval.marker = Marker::kSquare;
      plotKeyWork.lines = false;
      plotKeyWork.marker = Marker::kDiamond;
      plotBudget.markers = false;
      std::vector<Series> series{plotWork, plotKeyWork};
      if (budgetOn && opt.paceFrames) series.push_back(plotInterval);
      if (budgetOn) series.push_back(plotBudget);
      HW_TRY(writePlot(opt.outDir + "/frame_times.png", series, po));
    }
    for (std::size_t s = 0; s < strips.size(); ++s)
      HW_TRY(writePng(opt.outDir + "/strip_" + std::to_string(stripInfo[s]["frame"].get<int>()) +
                          ".png",
                      strips[s]));
    if (opt.keepFrames) {
      HW_TRY(writeFileAtomic(opt.outDir + "/report.json", result.report.dump(1)));
    } else {
      // Same document: the streamed frames, then the summary.
      std::string text = "{\n\"frames\": [";
      std::fflush(framesFile);
      const long size = std::ftell(framesFile);
      std::rewind(framesFile);
      const std::size_t start = text.size();
      text.resize(start + static_cast<std::size_t>(size > 0 ? size : 0));
      if (size > 0 && std::fread(text.data() + start, 1, static_cast<std::size_t>(size), framesFile) !=
                          static_cast<std::size_t>(size))
        return makeError("cannot read back " + framesScratch);
      text += "\n],\n\"summary\": " + summary.dump(1) + "\n}\n";
      HW_TRY(writeFileAtomic(opt.outDir + "/report.json", text));
    }
  }
  return result;
}

}  // namespace hw::bench
