#include "session/in_between.h"

#include <utility>

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
    st.backgroundDrawn = ps.backgroundDrawn;
    st.foregroundUncovered = ps.uncoveredByForeground;
    Stopwatch sc;
    if (ps.uncovered == 0 && opt_.skipPrevious) {
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
    st.quadsForeground = ps.quadsForeground;
    st.quadsBackground = ps.quadsBackground;
    st.backgroundCulled = ps.backgroundCulled;
    st.warpAMs = ps.foregroundMs;
    st.warpBMs = ps.backgroundMs;
    st.readbackMs = ps.readbackMs;
    st.cullMs = ps.cullMs;
  } else {
    warp::WarpStats wa, wb;
    HW_TRY(warper.warp(foreground, cam, layerA_, &wa));
    st.backgroundDrawn = background != nullptr && !(opt_.skipBackground && wa.uncovered == 0);
    st.foregroundUncovered = wa.uncovered;
    if (st.backgroundDrawn) HW_TRY(warper.warp(*background, cam, layerB_, &wb));
    Stopwatch sc;
    gapfill::compose(layerA_, st.backgroundDrawn ? &layerB_ : nullptr, previous, opt_.compose,
                     frame);
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

Status InBetweenStep::drawNear(const NearGeometry& near, const Camera& cam,
                               const Image<float>& behindZ, gapfill::Frame& frame,
                               InBetweenStats& st) {
  keyframe::RenderStats rs;
  Stopwatch sw;
  HW_TRY(near.renderer->renderNear(cam, near.eyes, near.eyeCount, opt_.nearDistance, nearColour_,
                                   nearEyeZ_, nearCovered_, &rs));
  const std::size_t n = nearColour_.size();
  const bool haveZ = behindZ.size() == n;
  int holes = 0, unfilled = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (nearCovered_.data()[p]) {
      const float z = haveZ ? behindZ.data()[p] : 0.0f;
      const bool empty = frame.holesBefore.data()[p] != 0 || z <= 0.0f;
      if (empty || nearEyeZ_.data()[p] < z) {
        clearLargeQuad(p);
        frame.colour.data()[p] = nearColour_.data()[p];
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
