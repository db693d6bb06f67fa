#include "session/presets.h"

namespace hw::session {

const char* presetName(Preset p) { return p == Preset::Paper ? "paper" : "default"; }

bool parsePreset(const std::string& s, Preset* out) {
  for (Preset p : {Preset::Default, Preset::Paper})
    if (s == presetName(p)) {
      *out = p;
      return true;
    }
  return false;
}

WalkOptions presetOptions(Preset p) {
  WalkOptions o;  // the paper's pipeline
  o.mode = FrameMode::Hybrid;
  if (p == Preset::Paper) return o;
  // Measured on 13 scenes x 13 configurations (docs/defaults.md): +0.7 dB
  // median PSNR over the paper's settings at 0.76x the in-between time.
  o.mode = FrameMode::Auto;
  o.lod.tauParallaxPx = 0.125;
  o.lod.planarity = keyframe::Planarity::RegionLocal;
  o.lod.mergeStrips = true;
  o.lod.splitMisfit = true;  // no leaf whose plane misses its pixels (docs/quad-validation.md)
  o.asyncKeyframes = true;
  // The larger holes drawn by the geometry renderer, within half a geometry
  // frame: +5 to +6 dB median and +3 to +12 dB p5 in-between PSNR on the
  // paths that warp, frames still below the geometry's (docs/results/
  // 2026-12-03/render-holes-default).
  o.renderHoles = true;
  o.renderHolesBudget = 0.5;
  return o;
}

PresetConflict differenceFromPaper(const WalkOptions& o) {
  const WalkOptions paper = presetOptions(Preset::Paper);
  if (o.mode != paper.mode) return {"--mode", frameModeName(paper.mode)};
  if (o.lod.tauParallaxPx != paper.lod.tauParallaxPx)
    return {"--tau-px", "none (tau in z' units)"};
  if (o.lod.criterion != paper.lod.criterion)
    return {"--criterion", keyframe::deltaCriterionName(paper.lod.criterion)};
  if (o.lod.planarity != paper.lod.planarity)
    return {"--planarity", keyframe::planarityName(paper.lod.planarity)};
  if (o.lod.mergeStrips != paper.lod.mergeStrips) return {"--merge-strips", "no merging"};
  if (o.lod.splitMisfit != paper.lod.splitMisfit) return {"--split-misfit", "no misfit split"};
  if (o.lod.tauGradient != paper.lod.tauGradient) return {"--tau-gradient", "0"};
  if (o.inBetween.compose.mode != paper.inBetween.compose.mode)
    return {"--compose", gapfill::composeModeName(paper.inBetween.compose.mode)};
  if (o.inBetween.nearDistance != paper.inBetween.nearDistance) return {"--near", "0"};
  if (o.inBetween.fallback != paper.inBetween.fallback) return {"--fallback", "copy"};
  if (o.renderHoles != paper.renderHoles) return {"--render-holes", "holes from the fallback"};
  if (o.warp.subdivision != paper.warp.subdivision)
    return {"--subdivide", warp::subdivisionName(paper.warp.subdivision)};
  if (o.mesh != paper.mesh) return {"--mesh", keyframe::meshMethodName(paper.mesh)};
  return {};
}

}  // namespace hw::session
