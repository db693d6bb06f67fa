#include "keyframe/geometry_renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <numeric>
#include <thread>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "core/gl/framebuffer.h"
#include "core/gl/gl_api.h"
#include "core/gl/shader.h"
#include "core/memory_budget.h"
#include "core/timer.h"
#include "scenes/simplify.h"

namespace hw::keyframe {
namespace {

// Lighting is view-independent (fixed sun + ambient) so that keyframe
// colours stay valid from nearby viewpoints, as image warping assumes.
constexpr const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
uniform mat4 uViewProj;  // double on the CPU, rounded once (see draw())
out vec3 vNormal;
out vec2 vUv;
void main() {
  vNormal = aNormal;
  vUv = aUv;
  gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

constexpr const char* kFragment = R"(#version 450 core
in vec3 vNormal;
in vec2 vUv;
uniform sampler2D uTex;
uniform int uHasTex;
uniform vec4 uBase;
uniform int uAlphaTest;
uniform float uCutoff;
uniform int uUnlit;
layout(location = 0) out vec4 oColour;
void main() {
  vec4 c = uBase;
  if (uHasTex != 0) c *= texture(uTex, vUv);
  if (uAlphaTest != 0 && c.a < uCutoff) discard;
  if (uUnlit == 0) {
    vec3 n = normalize(gl_FrontFacing ? vNormal : -vNormal);
    const vec3 sun = normalize(vec3(0.45, 0.8, 0.35));
    float d = max(dot(n, sun), 0.0);
    float sky = 0.5 + 0.5 * n.y;
    c.rgb *= 0.25 + 0.15 * sky + 0.6 * d;
  }
  oColour = vec4(c.rgb, 1.0);
}
)";

// A run of triangles in the index buffer with its bounds: a mesh, or one of
// its clusters.
struct Range {
  std::size_t firstIndex = 0, indexCount = 0;
  glm::vec3 lo{0.0f}, hi{0.0f};
};

struct DrawItem {
  Range all;                                   // bounds: the union of its clusters'
  Range simplifiedAll;                         // RenderOptions::simplifiedRects: its copy
  std::size_t clusterBegin = 0, clusterEnd = 0;  // into GlGeometryRenderer::clusters_
  int material = 0;
};

enum class Side { Outside, Straddles, Inside };

class GlGeometryRenderer final : public GeometryRenderer {
 public:
  ~GlGeometryRenderer() override {
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (vbo_) glDeleteBuffers(1, &vbo_);
    if (ibo_) glDeleteBuffers(1, &ibo_);
    if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  }

  Status init(const scenes::Scene& scene, const RenderOptions& options) {
    options_ = options;
    materials_ = scene.materials;
    if (materials_.empty()) materials_.push_back(scenes::Material{});
    sky_ = scene.skyColour;
    triangles_ = scene.triangleCount();
    auto prog = gl::Program::build("geometry", kVertex, kFragment);
    if (!prog) return prog.error();
    program_ = std::move(*prog);
    uViewProj_ = program_.uniform("uViewProj");
    uTex_ = program_.uniform("uTex");
    uHasTex_ = program_.uniform("uHasTex");
    uBase_ = program_.uniform("uBase");
    uAlphaTest_ = program_.uniform("uAlphaTest");
    uCutoff_ = program_.uniform("uCutoff");
    uUnlit_ = program_.uniform("uUnlit");

    // One vertex and one index buffer for the whole scene; meshes are index
    // ranges with indices rebased to global vertex numbers.
    std::size_t nv = 0, ni = 0;
    for (const auto& m : scene.meshes) {
      nv += m.vertices.size();
      ni += m.indices.size();
    }
    std::vector<scenes::Vertex> verts;
    std::vector<std::uint32_t> idx;
    verts.reserve(nv);
    idx.reserve(ni);
    // RenderOptions::simplifiedRects: each item's copy, its clusters' ranges
    // in the same order, appended after every item's own indices. Meshes are
    // simplified on every core (they are independent).
    std::vector<std::uint32_t> simplifiedIdx;
    std::vector<scenes::SimplifiedTriangles> simplified;
    std::uint64_t simplifyBytes = 0;
    if (options.simplifiedRects) {
      simplifyBytes = simplifyWorkingBytes(scene);
      HW_TRY(chargeMemory(simplifyBytes, "the simplified copy of the scene (--simplify-holes) while it is made",
                          "--max-memory raises the budget; --no-simplify-holes draws the hole "
                          "rectangles from the scene itself"));
    }
    struct Release {
      std::uint64_t bytes;
      ~Release() { releaseMemory(bytes); }
    } release{simplifyBytes};
    if (options.simplifiedRects) simplified = simplifyMeshes(scene);
    // Clusters come mesh by mesh, in order: the first of each mesh.
    const std::vector<scenes::Cluster> cs = scenes::clusterScene(scene, options.clusters);
    std::vector<std::size_t> firstCluster(scene.meshes.size() + 1, cs.size());
    for (std::size_t c = cs.size(); c-- > 0;) firstCluster[cs[c].mesh] = c;
    for (std::size_t m = scene.meshes.size(); m-- > 0;)
      firstCluster[m] = std::min(firstCluster[m], firstCluster[m + 1]);
    std::vector<std::size_t> order(scene.meshes.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return scene.meshes[a].material < scene.meshes[b].material;
    });
    for (std::size_t k : order) {
      const auto& m = scene.meshes[k];
      if (m.indices.empty()) continue;
      if (m.material < 0 || m.material >= static_cast<int>(materials_.size()))
        return makeError("scene " + scene.name + ": mesh '" + m.name + "' uses material " +
                         std::to_string(m.material) + " but the scene has " +
                         std::to_string(materials_.size()));
      DrawItem d;
      d.all.firstIndex = idx.size();
      d.all.indexCount = m.indices.size() / 3 * 3;
      d.material = m.material;
      d.clusterBegin = clusters_.size();
      d.all.lo = glm::vec3(std::numeric_limits<float>::max());
      d.all.hi = glm::vec3(-std::numeric_limits<float>::max());
      for (std::size_t c = firstCluster[k]; c < firstCluster[k + 1]; ++c) {
        Range r;
        r.firstIndex = d.all.firstIndex + 3 * std::size_t(cs[c].firstTriangle);
        r.indexCount = 3 * std::size_t(cs[c].triangleCount);
        r.lo = cs[c].boundsMin;
        r.hi = cs[c].boundsMax;
        d.all.lo = glm::min(d.all.lo, r.lo);
        d.all.hi = glm::max(d.all.hi, r.hi);
        clusters_.push_back(r);
      }
      d.clusterEnd = clusters_.size();
      if (d.clusterBegin == d.clusterEnd) d.all.lo = d.all.hi = glm::vec3(0.0f);
      const auto base = static_cast<std::uint32_t>(verts.size());
      for (std::uint32_t i : m.indices) {
        if (i >= m.vertices.size())
          return makeError("scene " + scene.name + ": mesh '" + m.name + "' has index " +
                           std::to_string(i) + " >= vertex count " +
                           std::to_string(m.vertices.size()));
        idx.push_back(base + i);
      }
      if (options.simplifiedRects && d.clusterBegin != d.clusterEnd)
        appendSimplified(m, simplified[k], base, d, simplifiedIdx);
      verts.insert(verts.end(), m.vertices.begin(), m.vertices.end());
      if (d.clusterBegin != d.clusterEnd) items_.push_back(d);  // no whole triangle: nothing to draw
    }
    if (options.simplifiedRects) {
      const std::size_t offset = idx.size();
      idx.insert(idx.end(), simplifiedIdx.begin(), simplifiedIdx.end());
      for (DrawItem& d : items_) d.simplifiedAll.firstIndex += offset;
      for (Range& r : simplified_) r.firstIndex += offset;
    }
    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    glGenBuffers(1, &vbo_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(scenes::Vertex)),
                 verts.data(), GL_STATIC_DRAW);
    glGenBuffers(1, &ibo_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * 4), idx.data(),
                 GL_STATIC_DRAW);
    const auto stride = static_cast<GLsizei>(sizeof(scenes::Vertex));
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<void*>(offsetof(scenes::Vertex, position)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<void*>(offsetof(scenes::Vertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<void*>(offsetof(scenes::Vertex, uv)));
    glBindVertexArray(0);

    for (const auto& t : scene.textures) {
      GLuint id = 0;
      glGenTextures(1, &id);
      glBindTexture(GL_TEXTURE_2D, id);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      // Row 0 (top) goes to t = 0, so uv.v = 0 samples the top row as the
      // scene convention says.
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, t.image.width(), t.image.height(), 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, t.image.data());
      glGenerateMipmap(GL_TEXTURE_2D);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
      textures_.push_back(id);
    }
    return gl::checkGlError("GeometryRenderer::create");
  }

  // What simplifyMeshes holds at most, estimated: the copies (indices,
  // sources, errors) and the working sets of as many of the largest meshes
  // as it simplifies at once (per triangle its corners and the edge map, per
  // vertex its attributes and fan list).
  static std::uint64_t simplifyWorkingBytes(const scenes::Scene& scene) {
    std::vector<std::uint64_t> work;
    std::uint64_t copies = 0;
    for (const scenes::Mesh& m : scene.meshes) {
      copies += 20ull * m.triangleCount();
      work.push_back(160ull * m.triangleCount() + 150ull * m.vertices.size());
    }
    std::sort(work.rbegin(), work.rend());
    const std::size_t n = std::min<std::size_t>(work.size(), simplifyThreads());
    return copies + std::accumulate(work.begin(), work.begin() + static_cast<std::ptrdiff_t>(n),
                                    std::uint64_t{0});
  }
  static unsigned simplifyThreads() { return std::clamp(std::thread::hardware_concurrency(), 1u, 8u); }

  // Every mesh's simplified copy (whole meshes: clusters cut the same runs).
  static std::vector<scenes::SimplifiedTriangles> simplifyMeshes(const scenes::Scene& scene) {
    std::vector<scenes::SimplifiedTriangles> out(scene.meshes.size());
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
      for (std::size_t k; (k = next++) < scene.meshes.size();) {
        const scenes::Mesh& m = scene.meshes[k];
        // A bad index fails init before the copy is used: leave it empty.
        if (std::any_of(m.indices.begin(), m.indices.end(),
                        [&](std::uint32_t i) { return i >= m.vertices.size(); }))
          continue;
        out[k] = scenes::simplifyTriangles(m, 0, static_cast<std::uint32_t>(m.triangleCount()),
                                           scenes::SimplifyOptions{});
      }
    };
    const unsigned threads = simplifyThreads();
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return out;
  }

  // Mesh `m`'s simplified copy `s` laid out by d's clusters: for each, the
  // simplified triangles that took the place of its own (an empty range when
  // none did), bounded by their corners; indices rebased by `base`, offsets
  // relative to the start of `out` (init moves them behind the full index
  // list).
  void appendSimplified(const scenes::Mesh& m, const scenes::SimplifiedTriangles& s,
                        std::uint32_t base, DrawItem& d, std::vector<std::uint32_t>& out) {
    d.simplifiedAll.firstIndex = out.size();  // bounds: d.all's (culling uses those)
    std::size_t k = 0;  // into s's triangles, whose sources increase
    for (std::size_t c = d.clusterBegin; c < d.clusterEnd; ++c) {
      const Range& full = clusters_[c];
      const std::size_t end = (full.firstIndex + full.indexCount - d.all.firstIndex) / 3;
      Range r;
      r.firstIndex = out.size();
      r.lo = glm::vec3(std::numeric_limits<float>::max());
      r.hi = glm::vec3(-std::numeric_limits<float>::max());
      for (; k < s.source.size() && s.source[k] < end; ++k)
        for (int j = 0; j < 3; ++j) {
          const std::uint32_t i = s.indices[3 * k + static_cast<std::size_t>(j)];
          out.push_back(base + i);
          r.lo = glm::min(r.lo, m.vertices[i].position);
          r.hi = glm::max(r.hi, m.vertices[i].position);
        }
      r.indexCount = out.size() - r.firstIndex;
      if (r.indexCount == 0) r.lo = r.hi = full.lo;
      simplified_.push_back(r);
    }
    d.simplifiedAll.indexCount = out.size() - d.simplifiedAll.firstIndex;
  }

  Status renderKeyframe(const Camera& camera, Keyframe& out, RenderStats* stats) override {
    RenderStats local;
    const NearFilter filter{NearFilter::Exclude, &camera.eye, 1, options_.keyframeExcludeNear};
    HW_TRY(draw(camera, local, options_.keyframeExcludeNear > 0 ? &filter : nullptr));
    Stopwatch sw;
    fbo_.readColour(out.colour);
    fbo_.readDepth(camera.nearPlane, camera.farPlane, out.zPrime, out.eyeZ, out.covered);
    out.camera = camera;
    out.depthMode = options_.depthMode;
    local.readbackMs = sw.ms();
    if (stats) *stats = local;
    return gl::checkGlError("GeometryRenderer::renderKeyframe");
  }

  Status renderColour(const Camera& camera, Image<Rgba8>& out, RenderStats* stats) override {
    RenderStats local;
    HW_TRY(draw(camera, local));
    Stopwatch sw;
    fbo_.readColour(out);
    local.readbackMs = sw.ms();
    if (stats) *stats = local;
    return gl::checkGlError("GeometryRenderer::renderColour");
  }

  Status renderColourRect(const Camera& camera, const PixelRect& rect, Image<Rgba8>& out,
                          RenderStats* stats) override {
    return renderColourRects(camera, &rect, 1, &out, stats);
  }

  Status renderColourRects(const Camera& camera, const PixelRect* rects, int count,
                           Image<Rgba8>* outs, RenderStats* stats) override {
    HW_TRY(checkRects(camera, rects, count));
    RenderStats local;
    if (count > 0) HW_TRY(draw(camera, local, nullptr, rects, count));
    Stopwatch sw;
    for (int k = 0; k < count; ++k)
      fbo_.readColourRect(rects[k].x0, rects[k].y0, rects[k].width(), rects[k].height(), outs[k]);
    local.readbackMs = sw.ms();
    if (stats) *stats = local;
    return gl::checkGlError("GeometryRenderer::renderColourRect");
  }

  Status renderColourTo(const Camera& camera, unsigned framebuffer, RenderStats* stats) override {
    RenderStats local;
    HW_TRY(draw(camera, local));
    Stopwatch sw;
    HW_TRY(checkTarget(framebuffer, camera));
    const PixelRect whole{0, 0, camera.width, camera.height};
    copyRects(framebuffer, camera, &whole, 1);
    local.readbackMs = sw.ms();
    if (stats) *stats = local;
    return gl::checkGlError("GeometryRenderer::renderColourTo");
  }

  Status renderColourRectsTo(const Camera& camera, const PixelRect* rects, int count,
                             unsigned framebuffer, RenderStats* stats) override {
    HW_TRY(checkRects(camera, rects, count));
    RenderStats local;
    if (count > 0) HW_TRY(draw(camera, local, nullptr, rects, count));
    Stopwatch sw;
    if (count > 0) {
      HW_TRY(checkTarget(framebuffer, camera));
      copyRects(framebuffer, camera, rects, count);
    }
    local.readbackMs = sw.ms();
    if (stats) *stats = local;
    return gl::checkGlError("GeometryRenderer::renderColourRectsTo");
  }

  Status renderNear(const Camera& camera, const glm::dvec3* eyes, int eyeCount, double distance,
                    Image<Rgba8>& colour, Image<float>& eyeZ, Image<std::uint8_t>& covered,
                    RenderStats* stats) override {
    RenderStats local;
    const NearFilter filter{NearFilter::Only, eyes, eyeCount, distance};
    HW_TRY(draw(camera, local, &filter));
    Stopwatch sw;
    fbo_.readColour(colour);
    fbo_.readDepth(camera.nearPlane, camera.farPlane, nearZPrime_, eyeZ, covered);
    local.readbackMs = sw.ms();
    if (stats) *stats = local;
    return gl::checkGlError("GeometryRenderer::renderNear");
  }

  void setFlushEvery(std::size_t triangles, std::function<void()> afterFlush) override {
    flushEvery_ = triangles;
    afterFlush_ = std::move(afterFlush);
  }

  std::size_t visibleTriangles(const Camera& camera) const override {
    std::size_t indices = 0;
    visitItems(frustumPlanes(viewProjection(camera)), nullptr, false,
               [&](const DrawItem&, std::size_t, std::size_t count, std::size_t) { indices += count; });
    return indices / 3;
  }
  std::size_t sceneTriangles() const override { return triangles_; }
  std::size_t sceneClusters() const override { return clusters_.size(); }
  const RenderOptions& options() const override { return options_; }

 private:
  Status ensureFbo(int w, int h) {
    if (w < 1 || h < 1)
      return makeError("camera image size " + std::to_string(w) + "x" + std::to_string(h) +
                       ": expected at least 1x1");
    if (fbo_.width() == w && fbo_.height() == h) return {};
    auto fb = gl::Framebuffer::create(w, h, options_.depthMode);
    if (!fb) return fb.error();
    fbo_ = std::move(*fb);
    return {};
  }

  static Status checkRects(const Camera& camera, const PixelRect* rects, int count) {
    for (int k = 0; k < count; ++k) {
      const PixelRect& rect = rects[k];
      if (rect.x0 < 0 || rect.y0 < 0 || rect.x1 > camera.width || rect.y1 > camera.height ||
          rect.width() < 1 || rect.height() < 1)
        return makeError("renderColourRect: rectangle [" + std::to_string(rect.x0) + ", " +
                         std::to_string(rect.x1) + ") x [" + std::to_string(rect.y0) + ", " +
                         std::to_string(rect.y1) + "): expected a non-empty rectangle inside the " +
                         std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                         " image");
    }
    return {};
  }

  // A copy target: a complete framebuffer whose colour attachment 0 is the
  // camera's size.
  static Status checkTarget(unsigned framebuffer, const Camera& camera) {
    if (framebuffer == 0 || !glIsFramebuffer(framebuffer))
      return makeError("copying the geometry to the GPU: " + std::to_string(framebuffer) +
                       " is not a framebuffer object");
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
    GLint type = 0, tex = 0, w = 0, h = 0;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type == GL_TEXTURE) {
      glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                            GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &tex);
      glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(tex));
      glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
      glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &h);
      glBindTexture(GL_TEXTURE_2D, 0);
    }
    if (type != GL_TEXTURE || w != camera.width || h != camera.height)
      return makeError("copying the geometry to the GPU: the target's colour attachment is " +
                       (type == GL_TEXTURE ? std::to_string(w) + "x" + std::to_string(h)
                                           : std::string("not a texture")) +
                       ", expected a " + std::to_string(camera.width) + "x" +
                       std::to_string(camera.height) + " texture");
    return {};
  }

  // The rectangles (row 0 = top) of the last draw into `framebuffer`'s
  // colour attachment 0, pixel for pixel.
  void copyRects(unsigned framebuffer, const Camera& camera, const PixelRect* rects, int count) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.id());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
    const GLenum attachment = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &attachment);
    glDisable(GL_SCISSOR_TEST);
    for (int k = 0; k < count; ++k) {
      const PixelRect& r = rects[k];
      const int y0 = camera.height - r.y1, y1 = camera.height - r.y0;
      glBlitFramebuffer(r.x0, y0, r.x1, y1, r.x0, y0, r.x1, y1, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glFinish();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  // Frustum planes from a double view-projection (Gribb-Hartmann), tested
  // against an AABB: outside one plane (p-vertex test), or inside all
  // (n-vertex test), or neither.
  static Side classify(const std::array<glm::dvec4, 6>& planes, const glm::vec3& lo,
                       const glm::vec3& hi) {
    Side s = Side::Inside;
    for (const auto& p : planes) {
      const glm::dvec3 v(p.x >= 0 ? hi.x : lo.x, p.y >= 0 ? hi.y : lo.y, p.z >= 0 ? hi.z : lo.z);
      if (p.x * v.x + p.y * v.y + p.z * v.z + p.w < 0) return Side::Outside;
      const glm::dvec3 n(p.x >= 0 ? lo.x : hi.x, p.y >= 0 ? lo.y : hi.y, p.z >= 0 ? lo.z : hi.z);
      if (p.x * n.x + p.y * n.y + p.z * n.z + p.w < 0) s = Side::Straddles;
    }
    return s;
  }

  struct NearFilter {
    enum Mode { Exclude, Only } mode;
    const glm::dvec3* eyes;
    int eyeCount;
    double distance;
    // Whether the bounds [lo, hi] come within `distance` of an eye.
    bool near(const glm::vec3& lo, const glm::vec3& hi) const {
      for (int k = 0; k < eyeCount; ++k)
        if (scenes::boxWithin(lo, hi, eyes[k], distance)) return true;
      return false;
    }
    bool skip(const glm::vec3& lo, const glm::vec3& hi) const {
      return near(lo, hi) == (mode == Exclude);
    }
  };

  glm::dmat4 viewProjection(const Camera& camera) const {
    return camera.projectionMatrix(options_.depthMode) * camera.viewMatrix();
  }

  // The view frustum's planes (Gribb-Hartmann) from a double view-projection.
  std::array<glm::dvec4, 6> frustumPlanes(const glm::dmat4& vp) const {
    std::array<glm::dvec4, 6> planes;
    const glm::dmat4 t = glm::transpose(vp);
    planes[0] = t[3] + t[0];
    planes[1] = t[3] - t[0];
    planes[2] = t[3] + t[1];
    planes[3] = t[3] - t[1];
    // Near and far are moved out by a hair (kDepthSlack of w in clip space)
    // so that a box the double test puts just outside, but that the float
    // transform puts just inside, is drawn: culling must leave the image as
    // it is.
    constexpr double kDepthSlack = 1e-5;
    if (options_.depthMode == DepthMode::Float32Reversed) {
      planes[4] = (1.0 + kDepthSlack) * t[3] - t[2];
      planes[5] = t[2] + kDepthSlack * t[3];
    } else {
      planes[4] = t[2] + (1.0 + kDepthSlack) * t[3];
      planes[5] = (1.0 + kDepthSlack) * t[3] - t[2];
    }
    return planes;
  }

  // With `rects`: only their pixels are cleared and drawn (scissor test), one
  // after the other, meshes culled against each one's sub-frustum; one
  // glFinish for all of them.
  Status draw(const Camera& camera, RenderStats& stats, const NearFilter* filter = nullptr,
              const PixelRect* rects = nullptr, int rectCount = 0) {
    HW_TRY(ensureFbo(camera.width, camera.height));
    Stopwatch sw;
    // The product is formed in double and rounded to float once. Float is
    // enough for the vertex stage: scene vertices are float in
    // every source format, and the shader's float uViewProj·aPos errs by
    // ≲ 2·2^-24·(|p| + |eye|) ≈ 3e-4 units at the largest scene's 2,400 units
    // from the origin (torcs:forza), ≤ 3e-4·f/z px = 0.07 px at z = 2 for
    // f = 443 px (512 px, 60°), 0.27 px at a 0.5 near plane; ≤ 0.04 px at
    // their near planes in the other scenes (indoor 33, oa_dm5 35, morse 75,
    // outdoor 160 units from the origin).
    // Depth precision is the depth mode's business (camera.h, stress suite).
    const glm::dmat4 vp = viewProjection(camera);
    const glm::mat4 vpf(vp);
    const glm::dmat4 t = glm::transpose(vp);
    const std::array<glm::dvec4, 6> planes = frustumPlanes(vp);
    program_.use();
    glUniformMatrix4fv(uViewProj_, 1, GL_FALSE, glm::value_ptr(vpf));
    glUniform1i(uTex_, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(vao_);
    glDisable(GL_BLEND);
    glFrontFace(GL_CCW);
    bound_ = -1;
    lastItem_ = nullptr;
    sinceFlush_ = 0;
    if (!rects) {
      fbo_.bindAndClear(sky_.r, sky_.g, sky_.b, 1.0f);
      drawItems(planes, filter, stats);
    } else {
      // One clear of the whole target (a fast clear; a scissored one is a
      // draw of its own): what lies outside the rectangles is never read.
      fbo_.bindAndClear(sky_.r, sky_.g, sky_.b, 1.0f);
      glEnable(GL_SCISSOR_TEST);
      for (int k = 0; k < rectCount; ++k) {
        const PixelRect& rect = rects[k];
        // GL's scissor box counts rows from the bottom.
        glScissor(rect.x0, camera.height - rect.y1, rect.width(), rect.height());
        // The rectangle's sub-frustum, grown by one pixel so that rounding
        // never culls a mesh with a fragment in it: x_ndc in [l, r], y_ndc in
        // [b, t].
        const double w = camera.width, h = camera.height;
        const double l = 2.0 * (rect.x0 - 1) / w - 1.0, r = 2.0 * (rect.x1 + 1) / w - 1.0;
        const double top = 1.0 - 2.0 * (rect.y0 - 1) / h,
                     bottom = 1.0 - 2.0 * (rect.y1 + 1) / h;
        std::array<glm::dvec4, 6> sub = planes;
        sub[0] = t[0] - l * t[3];
        sub[1] = r * t[3] - t[0];
        sub[2] = t[1] - bottom * t[3];
        sub[3] = top * t[3] - t[1];
        drawItems(sub, filter, stats, options_.simplifiedRects);
      }
      glDisable(GL_SCISSOR_TEST);
    }
    glBindVertexArray(0);
    glFinish();
    stats.drawMs = sw.ms();
    return {};
  }

  // Every item inside `planes` (the frustum, or a rectangle's), clusters
  // culled, near-filtered.
  void drawItems(const std::array<glm::dvec4, 6>& planes, const NearFilter* filter,
                 RenderStats& stats, bool simplified = false) {
    visitItems(planes, filter, simplified,
               [&](const DrawItem& d, std::size_t first, std::size_t count, std::size_t clusters) {
                 drawRange(d, first, count, clusters, stats);
               });
  }

  // The ranges drawItems draws, in its order: visit(item, firstIndex,
  // indexCount, clusters) for each; from the simplified copy if `simplified`.
  template <typename Visit>
  void visitItems(const std::array<glm::dvec4, 6>& planes, const NearFilter* filter,
                  bool simplified, Visit&& visit) const {
    const std::vector<Range>& clusters = simplified ? simplified_ : clusters_;
    for (const DrawItem& d : items_) {
      const Range& all = simplified ? d.simplifiedAll : d.all;
      Side side = Side::Inside;
      if (options_.frustumCulling) {
        side = classify(planes, d.all.lo, d.all.hi);
        if (side == Side::Outside) continue;
      }
      // A cluster's bounds lie within its mesh's: a mesh not near an eye has
      // no cluster near one.
      const bool meshNear = filter && filter->near(d.all.lo, d.all.hi);
      if (filter && !meshNear && filter->mode == NearFilter::Only) continue;
      if (!options_.clusterCulling) {
        if (filter && filter->skip(d.all.lo, d.all.hi)) continue;
        visit(d, all.firstIndex, all.indexCount, d.clusterEnd - d.clusterBegin);
        continue;
      }
      if (side == Side::Inside && !meshNear) {
        visit(d, all.firstIndex, all.indexCount, d.clusterEnd - d.clusterBegin);
        continue;
      }
      // Consecutive clusters drawn go out as one draw, so the triangles keep
      // the mesh's order.
      std::size_t runFirst = 0, runCount = 0, runClusters = 0;
      for (std::size_t c = d.clusterBegin; c < d.clusterEnd; ++c) {
        const Range& r = clusters[c];
        if (r.indexCount == 0 ||
            (side != Side::Inside && classify(planes, r.lo, r.hi) == Side::Outside) ||
            (meshNear && filter->skip(r.lo, r.hi)))
          continue;
        if (runCount > 0 && runFirst + runCount == r.firstIndex) {
          runCount += r.indexCount;
          ++runClusters;
          continue;
        }
        if (runCount > 0) visit(d, runFirst, runCount, runClusters);
        runFirst = r.firstIndex;
        runCount = r.indexCount;
        runClusters = 1;
      }
      if (runCount > 0) visit(d, runFirst, runCount, runClusters);
    }
  }

  // One draw of `indexCount` indices from `firstIndex`, part of item `d`
  // (its material bound first if another one is).
  void drawRange(const DrawItem& d, std::size_t firstIndex, std::size_t indexCount,
                 std::size_t clusters, RenderStats& stats) {
    if (d.material != bound_) {
      const scenes::Material& m = materials_[static_cast<std::size_t>(d.material)];
      const bool hasTex = m.texture >= 0 && m.texture < static_cast<int>(textures_.size());
      glUniform1i(uHasTex_, hasTex ? 1 : 0);
      if (hasTex) glBindTexture(GL_TEXTURE_2D, textures_[static_cast<std::size_t>(m.texture)]);
      glUniform4f(uBase_, m.baseColour.r, m.baseColour.g, m.baseColour.b, m.baseColour.a);
      glUniform1i(uAlphaTest_, m.alphaTest ? 1 : 0);
      glUniform1f(uCutoff_, m.alphaCutoff);
      glUniform1i(uUnlit_, m.unlit ? 1 : 0);
      if (m.twoSided) {
        glDisable(GL_CULL_FACE);
      } else {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
      }
      bound_ = d.material;
    }
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indexCount), GL_UNSIGNED_INT,
                   reinterpret_cast<void*>(firstIndex * sizeof(std::uint32_t)));
    if (&d != lastItem_) ++stats.meshesDrawn;
    lastItem_ = &d;
    ++stats.drawCalls;
    stats.clustersDrawn += clusters;
    stats.trianglesDrawn += indexCount / 3;
    sinceFlush_ += indexCount / 3;
    if (flushEvery_ > 0 && sinceFlush_ >= flushEvery_) {
      glFlush();
      sinceFlush_ = 0;
      if (afterFlush_) afterFlush_();
    }
  }

  RenderOptions options_;
  int bound_ = -1;                       // draw(): the material bound
  const DrawItem* lastItem_ = nullptr;   // draw(): the item of the last draw
  std::size_t sinceFlush_ = 0;           // draw(): triangles since the last flush
  std::size_t flushEvery_ = 0;
  std::function<void()> afterFlush_;
  std::vector<scenes::Material> materials_;
  glm::vec3 sky_{0.0f};
  std::size_t triangles_ = 0;
  gl::Program program_;
  int uViewProj_ = -1, uTex_ = -1, uHasTex_ = -1, uBase_ = -1, uAlphaTest_ = -1, uCutoff_ = -1,
      uUnlit_ = -1;
  GLuint vao_ = 0, vbo_ = 0, ibo_ = 0;
  std::vector<GLuint> textures_;
  std::vector<DrawItem> items_;
  std::vector<Range> clusters_;  // each item's clusters in its index range, in order
  std::vector<Range> simplified_;  // RenderOptions::simplifiedRects: clusters_[c]'s copy
  gl::Framebuffer fbo_;
  Image<double> nearZPrime_;  // renderNear's scratch
};

}  // namespace

Result<std::unique_ptr<GeometryRenderer>> GeometryRenderer::create(const scenes::Scene& scene,
                                                                   const RenderOptions& options) {
  auto r = std::make_unique<GlGeometryRenderer>();
  // Name the scene: an upload that runs out of GPU (or llvmpipe) memory
  // otherwise says only which GL call failed.
  if (Status ok = r->init(scene, options); !ok)
    return makeError("scene " + scene.name + " (" + std::to_string(scene.triangleCount()) +
                     " triangles, " + std::to_string(scene.textures.size()) +
                     " textures): " + ok.error().message);
  return std::unique_ptr<GeometryRenderer>(std::move(r));
}

}  // namespace hw::keyframe
