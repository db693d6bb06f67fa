#include "session/in_between.h"

#include <utility>

#include "core/check.h"
#include "core/timer.h"

namespace hw::session {
namespace {

void resizeFrame(gapfill::Frame& frame, int width, int height) {
  if (frame.colour.width() == width && frame.colour.height() == height) return;
  frame.colour.resize(width, height);
  frame.holesBefore.resize(width, height);
  frame.valid.resize(width, height);
}

void markNoHoles(gapfill::Frame& frame) {
  frame.holesBefore.fill(0);
  frame.valid.fill(1);
  frame.holeFractionBefore = frame.holeFractionAfter = 0;
}

}  // namespace

void setPairStats(const warp::PairStats& ps, InBetweenStats& st) {
  st.fused = true;
  st.backgroundDrawn = ps.backgroundDrawn;
  st.foregroundUncovered = ps.uncoveredByForeground;
  st.quadsForeground = ps.quadsForeground;
  st.quadsBackground = ps.quadsBackground;
  st.backgroundCulled = ps.backgroundCulled;
  st.warpAMs = ps.foregroundMs;
  st.warpBMs = ps.backgroundMs;
  st.readbackMs = ps.readbackMs;
  st.cullMs = ps.cullMs;
}

void showKeyframe(const Image<Rgba8>& colour, gapfill::Frame& frame) {
  if (&colour == &frame.colour) {  // rendered in place
    if (frame.valid.width() != colour.width() || frame.valid.height() != colour.height()) {
      frame.holesBefore.resize(colour.width(), colour.height());
      frame.valid.resize(colour.width(), colour.height());
    }
  } else {
    resizeFrame(frame, colour.width(), colour.height());
    frame.colour = colour;
  }
  markNoHoles(frame);
}

void setKeyframeDepth(const keyframe::Keyframe& kf, gapfill::Frame& frame) {
  HW_CHECK_EQ(kf.eyeZ.width(), frame.colour.width());
  HW_CHECK_EQ(kf.eyeZ.height(), frame.colour.height());
  if (frame.eyeZ.width() != kf.eyeZ.width() || frame.eyeZ.height() != kf.eyeZ.height())
    frame.eyeZ.resize(kf.eyeZ.width(), kf.eyeZ.height());
  for (std::size_t p = 0; p < kf.eyeZ.size(); ++p) {
    const float z = kf.eyeZ.data()[p];
    frame.eyeZ.data()[p] = z > 0.0f ? z : warp::kSkyEyeZ;
  }
  frame.camera = kf.camera;
}

void InBetweenStep::clearLargeQuad(std::size_t p) {
  for (warp::Layer* l : {&layerA_, &layerB_})
    if (p < l->largeQuad.size()) l->largeQuad.data()[p] = 0;
}

Status InBetweenStep::draw(warp::Warper& warper, const warp::WarpSource& foreground,
                           const warp::WarpSource* background, const Camera& cam,
                           const gapfill::Frame* previous, const NearGeometry* near,
                           gapfill::Frame& frame, InBetweenStats& st) {
  st = InBetweenStats{};
  st.fused = opt_.fused();
  if (st.fused) {
    warp::PairStats ps;
    HW_TRY(warper.warpPair(foreground, background, cam, layerA_, opt_.skipBackground, &ps));
    setPairStats(ps, st);
    Stopwatch sc;
    if (opt_.reprojects()) {
      gapfill::compose(layerA_, nullptr, nullptr, opt_.compose, frame);
      frame.fromForeground -= ps.fromBackground;
      frame.fromBackground = ps.fromBackground;
      gapfill::layerDepth(layerA_, nullptr, false, frame);
      HW_TRY(fillFromPrevious(cam, previous, frame, st));
    } else if (ps.uncovered == 0 && opt_.skipPrevious) {
      // Nothing to fill: the layer image is the frame (buffers swapped, no copy).
      st.previousSkipped = true;
      resizeFrame(frame, cam.width, cam.height);
      std::swap(frame.colour, layerA_.colour);
      markNoHoles(frame);
      frame.fromForeground = cam.width * cam.height - ps.fromBackground;
      frame.fromBackground = ps.fromBackground;
      frame.fromPrevious = frame.unfilled = 0;
    } else {
      gapfill::compose(layerA_, nullptr, previous, opt_.compose, frame);
      frame.fromForeground -= ps.fromBackground;
      frame.fromBackground = ps.fromBackground;
    }
    st.composeMs = sc.ms();
  } else {
    warp::WarpStats wa, wb;
    HW_TRY(warper.warp(foreground, cam, layerA_, &wa));
    st.backgroundDrawn =
        background != nullptr && !(opt_.skipsBackground() && wa.uncovered == 0);
    st.foregroundUncovered = wa.uncovered;
    if (st.backgroundDrawn) HW_TRY(warper.warp(*background, cam, layerB_, &wb));
    Stopwatch sc;
    const warp::Layer* layerB = st.backgroundDrawn ? &layerB_ : nullptr;
    gapfill::BlendViews views;
    if (opt_.compose.mode == gapfill::ComposeMode::Blend && layerB) {
      views.camera = cam;
      views.foregroundEye = foreground.keyframeCamera().eye;
      views.backgroundEye = background->keyframeCamera().eye;
    }
    if (opt_.reprojects()) {
      gapfill::compose(layerA_, layerB, nullptr, opt_.compose, &views, frame);
      gapfill::layerDepth(layerA_, layerB, opt_.compose.mode != gapfill::ComposeMode::Overlay,
                          frame);
      HW_TRY(fillFromPrevious(cam, previous, frame, st));
    } else {
      gapfill::compose(layerA_, layerB, previous, opt_.compose, &views, frame);
    }
    st.composeMs = sc.ms();
    st.quadsForeground = wa.quads;
    st.quadsBackground = wb.quads;
    st.warpAMs = wa.drawMs + wa.readbackMs;
    st.warpBMs = wb.drawMs + wb.readbackMs;
    st.warpADrawMs = wa.drawMs;
    st.warpBDrawMs = wb.drawMs;
    st.readbackMs = wa.readbackMs + wb.readbackMs;
  }
  if (near && opt_.nearDistance > 0) {
    // The layers' eye z: the composed one (fused) or the foreground's where it
    // covers, else the background's (separate).
    if (!st.fused && st.backgroundDrawn && layerB_.eyeZ.size() == layerA_.eyeZ.size()) {
      for (std::size_t p = 0; p < layerA_.eyeZ.size(); ++p)
        if (!layerA_.coverage.data()[p]) layerA_.eyeZ.data()[p] = layerB_.eyeZ.data()[p];
    }
    HW_TRY(drawNear(*near, cam, layerA_.eyeZ, frame, st));
  }
  return {};
}

Status InBetweenStep::fillFromPrevious(const Camera& cam, const gapfill::Frame* previous,
                                       gapfill::Frame& frame, InBetweenStats& st) {
  frame.camera = cam;
  if (previous == nullptr || frame.unfilled == 0) return {};
  HW_CHECK_EQ(previous->eyeZ.width(), previous->colour.width());
  HW_CHECK_EQ(previous->eyeZ.height(), previous->colour.height());
  Stopwatch sw;
  gapfill::reprojectFrame(*previous, cam, reprojected_, &frame.valid);
  const gapfill::FillStats fs = gapfill::fillHoles(reprojected_, previous, frame);
  st.reprojectedPixels = fs.reprojected;
  st.copiedPixels = fs.copied;
  st.fallbackMs = sw.ms();
  return {};
}

Status InBetweenStep::drawNear(const NearGeometry& near, const Camera& cam,
                               const Image<float>& behindZ, gapfill::Frame& frame,
                               InBetweenStats& st) {
  keyframe::RenderStats rs;
  Stopwatch sw;
  // The keyframes' eyes (what they left out) and the frame's own (NearGeometry).
  glm::dvec3 eyes[3];
  int eyeCount = 0;
  for (int k = 0; k < near.eyeCount && k < 2; ++k) eyes[eyeCount++] = near.eyes[k];
  if (eyeCount == 0 || eyes[0] != cam.eye) eyes[eyeCount++] = cam.eye;
  HW_TRY(near.renderer->renderNear(cam, eyes, eyeCount, opt_.nearDistance, nearColour_, nearEyeZ_,
                                   nearCovered_, &rs));
  const std::size_t n = nearColour_.size();
  const bool haveZ = behindZ.size() == n;
  const bool frameZ = frame.eyeZ.size() == n;  // the reprojected fallback's depth
  int holes = 0, unfilled = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (nearCovered_.data()[p]) {
      const float z = haveZ ? behindZ.data()[p] : 0.0f;
      const bool empty = frame.holesBefore.data()[p] != 0 || z <= 0.0f;
      if (empty || nearEyeZ_.data()[p] < z) {
        clearLargeQuad(p);
        frame.colour.data()[p] = nearColour_.data()[p];
        if (frameZ) frame.eyeZ.data()[p] = nearEyeZ_.data()[p];
        frame.holesBefore.data()[p] = 0;
        frame.valid.data()[p] = 1;
      }
    }
    holes += frame.holesBefore.data()[p];
    unfilled += frame.valid.data()[p] == 0;
  }
  frame.holeFractionBefore = n ? double(holes) / double(n) : 0.0;
  frame.holeFractionAfter = n ? double(unfilled) / double(n) : 0.0;
  st.nearMs = sw.ms();
  st.nearDrawMs = rs.drawMs;
  return {};
}

}  // namespace hw::session
