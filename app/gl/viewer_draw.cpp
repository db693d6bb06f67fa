// The viewer on screen: the composed frame as a full-screen triangle, the
// debug views (hole mask, quad outlines, the foreground keyframe's quad
// overlay), the HUD (stb_easy_font text), PSNR on demand and screenshots.
#include <stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "app/gl/viewer_impl.h"
#include "core/file_io.h"
#include "core/gl/gl_api.h"
#include "core/metrics.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/overlay.h"

namespace hw::app::viewer_detail {
namespace {

const char* kDisplayVs = R"(#version 450 core
out vec2 vUv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  vUv = vec2(p.x, 1.0 - p.y);  // texture row 0 is the image's top row
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";
const char* kDisplayFs = R"(#version 450 core
in vec2 vUv;
uniform sampler2D colourTex;
uniform sampler2D holeTex;
uniform int showHoles;
uniform int flipColour;  // the colour texture's row 0 is the bottom (a frame kept on the GPU)
out vec4 outColour;
void main() {
  vec3 c = texture(colourTex, flipColour != 0 ? vec2(vUv.x, 1.0 - vUv.y) : vUv).rgb;
  if (showHoles != 0 && texture(holeTex, vUv).r > 0.5) c = mix(c, vec3(1.0, 0.0, 0.0), 0.7);
  outColour = vec4(c, 1.0);
})";
const char* kLineVs = R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 viewProj;
void main() { gl_Position = viewProj * vec4(position, 1.0); })";
const char* kLineFs = R"(#version 450 core
uniform vec4 colour;
out vec4 outColour;
void main() { outColour = colour; })";
const char* kHudVs = R"(#version 450 core
layout(location = 0) in vec2 position;  // pixels, y down
layout(location = 1) in vec4 colour;
uniform vec2 screen;
uniform float scale;
out vec4 vColour;
void main() {
  vec2 p = position * scale;
  gl_Position = vec4(p.x / screen.x * 2.0 - 1.0, 1.0 - p.y / screen.y * 2.0, 0.0, 1.0);
  vColour = colour;
})";
const char* kHudFs = R"(#version 450 core
in vec4 vColour;
out vec4 outColour;
void main() { outColour = vColour; })";

void setFloatMatrix(int location, const glm::dmat4& m) {
  float f[16];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) f[c * 4 + r] = static_cast<float>(m[c][r]);
  glUniformMatrix4fv(location, 1, GL_FALSE, f);
}
}  // namespace

// Programs, vertex arrays, the HUD's buffers and the display textures, in
// the window's context.
Status Viewer::createGlResources() {
  auto dp = gl::Program::build("viewer display", kDisplayVs, kDisplayFs);
  if (!dp) return dp.error();
  displayProg_ = std::move(*dp);
  auto lp = gl::Program::build("viewer lines", kLineVs, kLineFs);
  if (!lp) return lp.error();
  lineProg_ = std::move(*lp);
  auto hp = gl::Program::build("viewer HUD", kHudVs, kHudFs);
  if (!hp) return hp.error();
  hudProg_ = std::move(*hp);
  displayProg_.use();
  glUniform1i(displayProg_.uniform("colourTex"), 0);
  glUniform1i(displayProg_.uniform("holeTex"), 1);
  uShowHoles_ = displayProg_.uniform("showHoles");
  uFlipColour_ = displayProg_.uniform("flipColour");
  uViewProj_ = lineProg_.uniform("viewProj");
  uLineColour_ = lineProg_.uniform("colour");
  uScreen_ = hudProg_.uniform("screen");
  uScale_ = hudProg_.uniform("scale");

  glGenVertexArrays(1, &emptyVao_);
  glGenVertexArrays(1, &lineVao_);
  glGenVertexArrays(1, &hudVao_);
  glGenBuffers(1, &hudVbo_);
  glGenBuffers(1, &hudIbo_);
  hudVerts_.resize(static_cast<std::size_t>(kHudMaxQuads) * 4);
  {
    std::vector<std::uint32_t> idx(static_cast<std::size_t>(kHudMaxQuads) * 6);
    for (std::uint32_t q = 0; q < static_cast<std::uint32_t>(kHudMaxQuads); ++q) {
      const std::uint32_t v = q * 4, o = q * 6;
      idx[o] = v, idx[o + 1] = v + 1, idx[o + 2] = v + 2;
      idx[o + 3] = v, idx[o + 4] = v + 2, idx[o + 5] = v + 3;
    }
    glBindVertexArray(hudVao_);
    glBindBuffer(GL_ARRAY_BUFFER, hudVbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(hudVerts_.size() * sizeof(EasyVertex)),
                 nullptr, GL_STREAM_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(EasyVertex), nullptr);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(EasyVertex),
                          reinterpret_cast<const void*>(offsetof(EasyVertex, c)));
    glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, hudIbo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(),
                 GL_STATIC_DRAW);
    glBindVertexArray(0);
  }
  glGenTextures(1, &colourTex_);
  glGenTextures(1, &holeTex_);
  glGenTextures(1, &overlayTex_);
  for (unsigned t : {colourTex_, holeTex_, overlayTex_}) {
    glBindTexture(GL_TEXTURE_2D, t);
    const int filter = t == overlayTex_ ? GL_LINEAR : GL_NEAREST;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  for (Slot& s : slots_) glGenBuffers(1, &s.lineVbo);
  return gl::checkGlError("viewer set-up");
}

Status Viewer::computePsnr() {
  Stopwatch sw;
  HW_TRY(renderer_->renderColour(cam_, reference_));
  engine_->readFrame(shownFrame_);
  const double p = psnr(shownFrame_, reference_);
  std::snprintf(psnrText_, sizeof psnrText_, "PSNR %.2f dB vs geometry (%s, frame %ld)",
                std::isfinite(p) ? p : 99.0, hybrid_ ? "hybrid" : "geometry", frameIndex_);
  if (!std::isfinite(p))
    std::snprintf(psnrText_, sizeof psnrText_, "PSNR inf dB vs geometry (identical, %s, frame %ld)",
                  hybrid_ ? "hybrid" : "geometry", frameIndex_);
  std::printf("%s\n", psnrText_);
  std::fflush(stdout);
  psnrUntil_ = clock_.ms() / 1000.0 + 2 * kMessageSeconds;
  return {};
}

void Viewer::hudBlock(float x, float y, char* text, const unsigned char colour[4]) {
  if (hudQuads_ + 1 >= kHudMaxQuads) return;
  // Translucent backdrop, then the text.
  const float w = static_cast<float>(stb_easy_font_width(text));
  const float h = static_cast<float>(stb_easy_font_height(text));
  const float pad = 3;
  EasyVertex* v = hudVerts_.data() + static_cast<std::ptrdiff_t>(hudQuads_) * 4;
  const float xs[4] = {x - pad, x + w + pad, x + w + pad, x - pad};
  const float ys[4] = {y - pad, y - pad, y + h + pad, y + h + pad};
  for (int i = 0; i < 4; ++i) v[i] = EasyVertex{xs[i], ys[i], 0, {0, 0, 0, 150}};
  ++hudQuads_;
  unsigned char c[4] = {colour[0], colour[1], colour[2], colour[3]};
  const int room = (kHudMaxQuads - hudQuads_) * 4 * static_cast<int>(sizeof(EasyVertex));
  hudQuads_ += stb_easy_font_print(
      x, y, text, c, hudVerts_.data() + static_cast<std::ptrdiff_t>(hudQuads_) * 4, room);
}

// The statistics block of the HUD into hudText_, at statsLevel_ (not Off).
void Viewer::hudStatsText() {
  const double fps = frameMsSmoothed_ > 0 ? 1000.0 / frameMsSmoothed_ : 0;
  int n = std::snprintf(hudText_, sizeof hudText_, "%s  %.1f fps (%.1f ms)  speed %.2f units/s%s%s",
                        autoMode_ ? (hybrid_ ? "auto: hybrid" : "auto: geometry")
                        : hybrid_ ? "hybrid"
                                  : "geometry",
                        fps, frameMsSmoothed_, moveSpeed_, play_ ? "  [playing]" : "",
                        recorder_.recording() ? "  [recording]" : "");
  auto append = [&](const char* fmt, auto... args) {
    if (n < 0 || n >= static_cast<int>(sizeof hudText_)) return;
    const int m = std::snprintf(hudText_ + n, sizeof hudText_ - static_cast<std::size_t>(n), fmt,
                                args...);
    n = m < 0 ? m : n + m;
  };
  if (statsLevel_ >= StatsLevel::Stages) {
    const FrameStats& s = stats_;
    if (s.hybrid) {
      append("\nwarp fg %.1f ms  bg + readback %.1f ms%s  compose %.1f ms (%s)%s\n"
             "quads %d + %d (%d layer%s)  holes %.2f%% -> %.2f%% after fill\n"
             "last keyframe: %s %.1f  LOD %.1f  upload %.1f ms, %d quads; %ld built, %ld read%s\n"
             "%s  keyframe every %.2f units / %.0f deg",
             s.warpAMs, s.warpBMs, s.backgroundSkipped ? " (bg skipped)" : "", s.composeMs,
             engine_->framesOnGpu() ? "on the GPU" : "on the CPU", s.direct ? "  (keyframe shown as is)" : "", s.quadsA, s.quadsB, s.layers,
             s.layers == 1 ? "" : "s", 100 * s.holesBefore, 100 * s.holesAfter,
             lastKeyframe_.fromDb       ? "read from the database"
             : lastKeyframe_.fromWorker ? "worker render (wall ms, paced)"
                                        : "render",
             lastKeyframe_.renderMs, lastKeyframe_.lodMs, lastKeyframe_.uploadMs,
             lastKeyframe_.quads, keyframesBuilt_ + keyframesFromWorker_, keyframesRead_,
             s.builtKeyframe || s.readKeyframe ? " (one this frame)" : "", thresholdText().c_str(),
             kfDistance_, kfAngle_ * 180 / kPi);
    } else {
      append("\ngeometry %.1f ms  %zu of %zu triangles drawn", s.geometryMs, s.trianglesDrawn,
             scene_.triangleCount());
    }
  }
  if (statsLevel_ < StatsLevel::Stalls) return;
  // Keyframe stalls (rendered or read in the frame, which waited for it)
  // and, with the worker, frames that warped older keyframes while the
  // next one was not ready.
  if (worker_)
    append("\nkeyframes async: %ld from the worker%s, last ready after %ld frames (%.0f ms); "
           "%ld stalls (max %.1f ms), %ld frames waited%s",
           keyframesFromWorker_, pendingId_ >= 0 ? " (one in flight)" : "", lastLatencyFrames_,
           lastLatencyMs_, keyframeStalls_, maxStallMs_, waitFrames_,
           stats_.waitedForKeyframe ? " (waiting)" : "");
  else
    append("\nkeyframes in the frame: %ld stalls (max %.1f ms)", keyframeStalls_, maxStallMs_);
}

void Viewer::drawHud() {
  hudQuads_ = 0;
  // stb_easy_font's glyphs are ~6 px: 1× up to 640 px wide, then in half steps up to 2×.
  const float scale =
      std::clamp(std::floor(static_cast<float>(width_) / 640.0f * 2.0f) / 2.0f, 1.0f, 2.0f);
  const unsigned char white[4] = {255, 255, 255, 255};
  const unsigned char yellow[4] = {255, 230, 80, 255};
  const double now = clock_.ms() / 1000.0;
  float y = 6;
  const float lineH = 12;
  if (statsLevel_ != StatsLevel::Off) {
    hudStatsText();
    hudBlock(6, y, hudText_, white);
    y += static_cast<float>(stb_easy_font_height(hudText_)) + lineH;
  }
  if (psnrText_[0] && now < psnrUntil_) {
    hudBlock(6, y, psnrText_, yellow);
    y += lineH + 4;
  }
  if (messageText_[0] && now < messageUntil_) {
    hudBlock(6, y, messageText_, yellow);
    y += lineH + 4;
  }
  if (help_) {
    std::snprintf(hudText_, sizeof hudText_, "%s", viewerKeyHelp().c_str());
    hudBlock(6, y + 4, hudText_, white);
  } else if (statsLevel_ != StatsLevel::Off && frameIndex_ < 200) {
    std::snprintf(hudText_, sizeof hudText_, "h: help");
    hudBlock(6, y, hudText_, white);
  }
  if (hudQuads_ == 0) return;
  hudProg_.use();
  glUniform2f(uScreen_, static_cast<float>(width_), static_cast<float>(height_));
  glUniform1f(uScale_, scale);
  glBindVertexArray(hudVao_);
  glBindBuffer(GL_ARRAY_BUFFER, hudVbo_);
  glBufferSubData(
      GL_ARRAY_BUFFER, 0,
      static_cast<GLsizeiptr>(static_cast<std::size_t>(hudQuads_) * 4 * sizeof(EasyVertex)),
      hudVerts_.data());
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDrawElements(GL_TRIANGLES, hudQuads_ * 6, GL_UNSIGNED_INT, nullptr);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
}

void Viewer::drawWindow() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glActiveTexture(GL_TEXTURE0);
  // A frame kept on the GPU is shown from its own texture; one drawn on the
  // CPU is uploaded.
  const bool onGpu = engine_->framesOnGpu() && engine_->frameTexture() != 0;
  if (onGpu) {
    glBindTexture(GL_TEXTURE_2D, engine_->frameTexture());
  } else {
    glBindTexture(GL_TEXTURE_2D, colourTex_);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE,
                    engine_->frame().colour.data());
  }
  const bool holes = holeMask_ && hybrid_;
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, holeTex_);
  if (holes)
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RED, GL_UNSIGNED_BYTE,
                    engine_->frame().holesBefore.data());
  displayProg_.use();
  glUniform1i(uShowHoles_, holes ? 1 : 0);
  glUniform1i(uFlipColour_, onGpu ? 1 : 0);
  glBindVertexArray(emptyVao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  if (wireframe_ && hybrid_) {
    lineProg_.use();
    setFloatMatrix(uViewProj_, cam_.projectionMatrix(DepthMode::Fixed24, true) * cam_.viewMatrix());
    glBindVertexArray(lineVao_);
    for (int i = 0; i < 2; ++i) {
      const Slot& s = slots_[static_cast<std::size_t>(i)];
      if (!s.valid || s.lineVertices == 0) continue;
      if (i == foregroundSlot_)
        glUniform4f(uLineColour_, 0.1f, 1.0f, 0.2f, 1.0f);
      else
        glUniform4f(uLineColour_, 1.0f, 0.6f, 0.1f, 1.0f);
      glBindBuffer(GL_ARRAY_BUFFER, s.lineVbo);
      glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
      glEnableVertexAttribArray(0);
      glDrawArrays(GL_LINES, 0, s.lineVertices);
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }

  if (overlay_ && hybrid_ && foregroundSlot_ >= 0 &&
      slots_[static_cast<std::size_t>(foregroundSlot_)].valid) {
    const Slot& s = slots_[static_cast<std::size_t>(foregroundSlot_)];
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, overlayTex_);
    if (overlaySerial_ != s.serial) {
      // Only when the foreground keyframe changes.
      const Image<Rgba8> img = keyframe::drawQuadOverlay(s.kf.colour, s.mesh);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img.width(), img.height(), 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, img.data());
      overlaySerial_ = s.serial;
      overlayW_ = img.width();
      overlayH_ = img.height();
    }
    const int w = std::max(1, width_ * 2 / 5),
              h = std::max(1, w * overlayH_ / std::max(1, overlayW_));
    displayProg_.use();
    glUniform1i(uShowHoles_, 0);
    glUniform1i(uFlipColour_, 0);
    glViewport(width_ - w - 8, 8, w, h);  // bottom right, clear of the HUD
    glBindVertexArray(emptyVao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glViewport(0, 0, width_, height_);
  }
  if (opt_.hud) drawHud();
  glActiveTexture(GL_TEXTURE0);
}

void Viewer::readWindow(Image<Rgba8>& out) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  readScratch_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, readScratch_.data());
  if (out.width() != width_ || out.height() != height_) out.resize(width_, height_);
  for (int y = 0; y < height_; ++y) {  // GL row 0 is the bottom
    const Rgba8* src = readScratch_.data() + static_cast<std::ptrdiff_t>(height_ - 1 - y) * width_;
    Rgba8* dst = out.data() + static_cast<std::ptrdiff_t>(y) * width_;
    for (int x = 0; x < width_; ++x) dst[x] = Rgba8{src[x].r, src[x].g, src[x].b, 255};
  }
}

Status Viewer::screenshot(const std::string& path) {
  readWindow(windowImage_);
  HW_TRY(gl::checkGlError("reading the window for a screenshot"));
  return writePng(path, windowImage_);
}

void Viewer::capture() {
  std::string name;
  for (int n = 0;; ++n) {
    name = "hybridwalk_screenshot_" + std::to_string(n) + ".png";
    if (!std::filesystem::exists(name)) break;
  }
  const Status s = screenshot(name);
  if (s)
    message("screenshot saved to " + name);
  else
    message("screenshot failed: " + s.error().message);
}

}  // namespace hw::app::viewer_detail
