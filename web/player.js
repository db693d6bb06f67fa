// The hybridwalk web player: plays a published walkthrough (docs/publish.md).
// Every frame between two keyframes is the keyframes' quad meshes
// backward-warped in WebGL 2 as the native warper does (Zheng et al. 1999
// §2.1; warp/gl/warper.cpp): projective texture coordinates, the nearer
// keyframe in front, the other only where it left pixels empty, and the
// previous frame where both miss (§2.2).

const kFormat = 'hybridwalk-web';
const kVersion = 1;
const kMeshMagic = 'HWWEBMSH';
const kMeshHeaderBytes = 24;
const kFloatsPerVertex = 6;
const kTieRelTol = 1e-9;  // gapfill::kForegroundTieRelTol

class LoadError extends Error {}

// hw32 (docs/publish.md): FNV-style over little-endian 32-bit words.
function hw32(bytes) {
  let h = 2166136261;
  const n = bytes.length, whole = n & ~3;
  const words = new Uint32Array(bytes.buffer, bytes.byteOffset, whole / 4);
  const aligned = bytes.byteOffset % 4 === 0;
  const dv = new DataView(bytes.buffer, bytes.byteOffset, n);
  for (let i = 0; i < whole / 4; ++i) {
    const w = aligned ? words[i] : dv.getUint32(4 * i, true);
    h = Math.imul(h ^ w, 16777619) >>> 0;
  }
  if (whole < n) {
    let w = 0;
    for (let k = 0; whole + k < n; ++k) w |= bytes[whole + k] << (8 * k);
    h = Math.imul(h ^ w, 16777619) >>> 0;
  }
  return (h ^ n) >>> 0;
}
const hex8 = (v) => v.toString(16).padStart(8, '0');

// ---- manifest -------------------------------------------------------------

function checkManifest(m) {
  const bad = (what) => { throw new LoadError(`manifest.json: ${what}`); };
  const isInt = (v, lo, hi) => Number.isInteger(v) && v >= lo && v <= hi;
  const vec3 = (v, where) => {
    if (!Array.isArray(v) || v.length !== 3 || !v.every(Number.isFinite))
      bad(`${where}: expected [x, y, z] of finite numbers, got ${JSON.stringify(v)}`);
  };
  if (m === null || typeof m !== 'object' || Array.isArray(m)) bad('expected a JSON object');
  if (m.format !== kFormat) bad(`format ${JSON.stringify(m.format)}, expected "${kFormat}"`);
  if (m.version !== kVersion)
    bad(`version ${JSON.stringify(m.version)}, this player reads version ${kVersion} (publish again)`);
  for (const k of ['width', 'height'])
    if (!isInt(m[k], 1, 16384)) bad(`${k} ${JSON.stringify(m[k])}, expected a whole number of pixels 1..16384`);
  if (!(m.fov_y_radians > 0 && m.fov_y_radians < Math.PI)) bad(`fov_y_radians ${m.fov_y_radians}, expected (0, pi)`);
  if (!(m.near > 0 && m.far > m.near && Number.isFinite(m.far))) bad(`near ${m.near}, far ${m.far}: expected 0 < near < far`);
  if (!Array.isArray(m.frames) || m.frames.length < 1) bad('frames: expected a non-empty array of cameras');
  m.frames.forEach((f, i) => {
    if (f === null || typeof f !== 'object') bad(`frames[${i}]: expected {eye, right, up, forward}`);
    for (const k of ['eye', 'right', 'up', 'forward']) vec3(f[k], `frames[${i}].${k}`);
  });
  if (!Array.isArray(m.keyframes) || m.keyframes.length < 1) bad('keyframes: expected a non-empty array');
  let last = -1;
  m.keyframes.forEach((k, i) => {
    const at = `keyframes[${i}]`;
    if (k === null || typeof k !== 'object') bad(`${at}: expected an object`);
    if (!isInt(k.frame, last + 1, m.frames.length - 1))
      bad(`${at}.frame ${JSON.stringify(k.frame)}: expected a frame index above ${last} and below ${m.frames.length}`);
    last = k.frame;
    vec3(k.eye, `${at}.eye`);
    for (const [key, ext] of [['colour', 'png'], ['mesh', 'mesh']]) {
      const e = k[key];
      if (e === null || typeof e !== 'object') bad(`${at}.${key}: expected {file, bytes, checksum}`);
      if (typeof e.file !== 'string' || !new RegExp(`^kf_[0-9]{6}\\.${ext}$`).test(e.file))
        bad(`${at}.${key}.file ${JSON.stringify(e.file)}: expected a name like kf_000010.${ext}`);
      if (!isInt(e.bytes, 1, 2 ** 31)) bad(`${at}.${key}.bytes ${JSON.stringify(e.bytes)}: expected a file size`);
      if (typeof e.checksum !== 'string' || !/^[0-9a-f]{8}$/.test(e.checksum))
        bad(`${at}.${key}.checksum ${JSON.stringify(e.checksum)}: expected 8 hex digits`);
    }
    for (const key of ['quads', 'sky_rects'])
      if (!isInt(k.mesh[key], 0, 2 ** 26)) bad(`${at}.mesh.${key} ${JSON.stringify(k.mesh[key])}: expected a count`);
  });
  if (m.keyframes[0].frame !== 0 || last !== m.frames.length - 1)
    bad(`keyframes run from frame ${m.keyframes[0].frame} to ${last}; expected the first (0) and last (${m.frames.length - 1}) frames`);
}

async function fetchBytes(name) {
  let r;
  try {
    r = await fetch(name, { cache: 'no-store' });
  } catch (e) {
    throw new LoadError(`${name}: could not be fetched (${e.message}); open the folder through a web server (docs/publish.md)`);
  }
  if (!r.ok) throw new LoadError(`${name}: HTTP ${r.status} ${r.statusText}, expected the file manifest.json lists`);
  return new Uint8Array(await r.arrayBuffer());
}

// `entry` as listed by `by` (manifest.json; index.html for the manifest itself).
function checkFile(entry, bytes, by = 'manifest.json') {
  if (bytes.length !== entry.bytes)
    throw new LoadError(`${entry.file}: ${bytes.length} bytes, ${by} says ${entry.bytes} (file ${bytes.length < entry.bytes ? 'truncated' : 'grown'} or replaced)`);
  const sum = hex8(hw32(bytes));
  if (sum !== entry.checksum)
    throw new LoadError(`${entry.file}: checksum ${sum}, ${by} says ${entry.checksum} (file corrupt, edited or replaced)`);
}

// docs/publish.md "Mesh file".
function parseMesh(entry, bytes) {
  const name = entry.file;
  const magic = String.fromCharCode(...bytes.subarray(0, 8));
  if (bytes.length < kMeshHeaderBytes || magic !== kMeshMagic)
    throw new LoadError(`${name}: not a published mesh (magic ${JSON.stringify(magic)}, expected "${kMeshMagic}")`);
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.length);
  const version = dv.getUint32(8, true), quads = dv.getUint32(12, true);
  const sky = dv.getUint32(16, true), floats = dv.getUint32(20, true);
  if (version !== kVersion) throw new LoadError(`${name}: mesh version ${version}, expected ${kVersion}`);
  if (floats !== kFloatsPerVertex) throw new LoadError(`${name}: ${floats} floats per vertex, expected ${kFloatsPerVertex}`);
  if (quads !== entry.quads || sky !== entry.sky_rects)
    throw new LoadError(`${name}: ${quads} quads and ${sky} sky rectangles, manifest.json says ${entry.quads} and ${entry.sky_rects}`);
  const want = kMeshHeaderBytes + (quads + sky) * 4 * kFloatsPerVertex * 4;
  if (bytes.length !== want)
    throw new LoadError(`${name}: ${bytes.length} bytes, expected ${want} for ${quads} quads and ${sky} sky rectangles`);
  const copy = bytes.slice(kMeshHeaderBytes);  // aligned for Float32Array
  return { quads, sky, vertices: new Float32Array(copy.buffer) };
}

// ---- camera maths (core/camera.cpp, in double as there) ------------------

const dot = (a, b) => { const t0 = a[0] * b[0], t1 = a[1] * b[1], t2 = a[2] * b[2]; return t0 + t1 + t2; };
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]];
const norm = (a) => { const l = Math.sqrt(dot(a, a)); return [a[0] / l, a[1] / l, a[2] / l]; };

// Column-major 4×4 (m[c*4 + r]), as GLM.
function viewMatrix(c) {
  const m = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  for (let k = 0; k < 3; ++k) {
    m[k * 4 + 0] = c.right[k];
    m[k * 4 + 1] = c.up[k];
    m[k * 4 + 2] = -c.forward[k];
  }
  m[12] = -dot(c.right, c.eye);
  m[13] = -dot(c.up, c.eye);
  m[14] = dot(c.forward, c.eye);
  return m;
}
// Fixed24 depth, far plane at infinity (WarpOptions::infiniteFar).
function projectionMatrix(v) {
  const fy = 0.5 * v.height / Math.tan(0.5 * v.fovY);
  const m = new Array(16).fill(0);
  m[0] = 2.0 * fy / v.width;
  m[5] = 2.0 * fy / v.height;
  m[11] = -1.0;
  m[10] = -1.0;
  m[14] = -2.0 * v.near;
  return m;
}
function mul(a, b) {  // GLM's a * b, summed in its order
  const r = new Array(16);
  for (let c = 0; c < 4; ++c)
    for (let row = 0; row < 4; ++row) {
      let s = a[0 * 4 + row] * b[c * 4 + 0];
      s += a[1 * 4 + row] * b[c * 4 + 1];
      s += a[2 * 4 + row] * b[c * 4 + 2];
      s += a[3 * 4 + row] * b[c * 4 + 3];
      r[c * 4 + row] = s;
    }
  return r;
}
function chooseForeground(eye, eyeA, eyeB) {  // gapfill::chooseForeground
  const a = sub(eye, eyeA), b = sub(eye, eyeB);
  const dA = Math.sqrt(dot(a, a)), dB = Math.sqrt(dot(b, b));
  if (Math.abs(dA - dB) <= kTieRelTol * (dA + dB)) return 0;
  return dA < dB ? 0 : 1;
}

// ---- WebGL ----------------------------------------------------------------

const kWarpVs = `#version 300 es
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aTex;  // (u·q, v·q, q), u, v normalised
uniform mat4 uViewProj;
uniform float uW;  // 1: quads; 0: sky rectangles (directions, points at infinity)
out vec3 vTex;
void main() {
  vTex = aTex;
  gl_Position = uViewProj * vec4(aPos, uW);
}`;
const kWarpFs = `#version 300 es
precision highp float;
precision highp sampler2D;
in vec3 vTex;
uniform sampler2D uKey;
out vec4 oColour;
void main() { oColour = vec4(textureProj(uKey, vTex).rgb, 1.0); }`;
const kFullVs = `#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}`;
// Alpha 1 = the pixel has content (Frame::valid); 0 = unfilled (black).
const kComposeFs = `#version 300 es
precision highp float;
uniform sampler2D uLayer;
uniform sampler2D uPrev;
uniform bool uHasPrev;
out vec4 o;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 l = texelFetch(uLayer, p, 0);
  if (l.a > 0.0) { o = vec4(l.rgb, 1.0); return; }
  vec4 q = uHasPrev ? texelFetch(uPrev, p, 0) : vec4(0.0);
  o = q.a > 0.0 ? vec4(q.rgb, 1.0) : vec4(0.0);
}`;
// A keyframe shown as it is (its image row 0 is the top; GL rows count from the bottom).
const kKeyFs = `#version 300 es
precision highp float;
uniform sampler2D uKey;
uniform int uHeight;
out vec4 o;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  o = vec4(texelFetch(uKey, ivec2(p.x, uHeight - 1 - p.y), 0).rgb, 1.0);
}`;

function program(gl, vs, fs, name) {
  const mk = (type, src) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(`${name} shader: ${gl.getShaderInfoLog(s)}`);
    return s;
  };
  const p = gl.createProgram();
  gl.attachShader(p, mk(gl.VERTEX_SHADER, vs));
  gl.attachShader(p, mk(gl.FRAGMENT_SHADER, fs));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(`${name} program: ${gl.getProgramInfoLog(p)}`);
  const u = {};
  const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < n; ++i) {
    const name2 = gl.getActiveUniform(p, i).name;
    u[name2] = gl.getUniformLocation(p, name2);
  }
  return { p, u };
}

function texture(gl, w, h, filter, source) {
  const t = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, t);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  if (source) {
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, source);
  } else {
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA8, w, h);
  }
  return t;
}

function framebuffer(gl, tex, depthStencil) {
  const f = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, f);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
  if (depthStencil) gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_STENCIL_ATTACHMENT, gl.RENDERBUFFER, depthStencil);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) throw new Error('WebGL framebuffer incomplete');
  return f;
}

class Warper {
  constructor(gl, m) {
    this.gl = gl;
    this.view = { width: m.width, height: m.height, fovY: m.fov_y_radians, near: m.near };
    this.warp = program(gl, kWarpVs, kWarpFs, 'warp');
    this.compose = program(gl, kFullVs, kComposeFs, 'compose');
    this.key = program(gl, kFullVs, kKeyFs, 'keyframe');
    this.emptyVao = gl.createVertexArray();
    const w = m.width, h = m.height;
    const ds = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, ds);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH24_STENCIL8, w, h);
    this.layerTex = texture(gl, w, h, gl.NEAREST);
    this.layerFbo = framebuffer(gl, this.layerTex, ds);
    this.frameTex = [texture(gl, w, h, gl.NEAREST), texture(gl, w, h, gl.NEAREST)];
    this.frameFbo = this.frameTex.map((t) => framebuffer(gl, t, null));
    this.cur = 0;          // frameTex[cur] holds the last frame
    this.havePrev = false;
    let most = 0;
    for (const k of m.keyframes) most = Math.max(most, k.mesh.quads + k.mesh.sky_rects);
    const idx = new Uint32Array(most * 6);  // each quad as triangles 0-1-2, 0-2-3
    for (let q = 0; q < most; ++q) idx.set([4 * q, 4 * q + 1, 4 * q + 2, 4 * q, 4 * q + 2, 4 * q + 3], 6 * q);
    this.ibo = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.ibo);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, idx, gl.STATIC_DRAW);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  upload(mesh, bitmap) {
    const gl = this.gl;
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const vbo = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, vbo);
    gl.bufferData(gl.ARRAY_BUFFER, mesh.vertices, gl.STATIC_DRAW);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.ibo);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 24, 0);
    gl.enableVertexAttribArray(1);
    gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 24, 12);
    gl.bindVertexArray(null);
    const tex = texture(gl, 0, 0, gl.LINEAR, bitmap);
    return { vao, tex, quads: mesh.quads, sky: mesh.sky };
  }

  drawSource(src, vp) {
    const gl = this.gl;
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, src.tex);
    gl.useProgram(this.warp.p);
    gl.uniformMatrix4fv(this.warp.u.uViewProj, false, vp);
    gl.uniform1i(this.warp.u.uKey, 0);
    gl.disable(gl.CULL_FACE);
    gl.disable(gl.BLEND);
    gl.bindVertexArray(src.vao);
    if (src.sky > 0) {  // behind everything: no depth test or write
      gl.disable(gl.DEPTH_TEST);
      gl.depthMask(false);
      gl.uniform1f(this.warp.u.uW, 0.0);
      gl.drawElements(gl.TRIANGLES, src.sky * 6, gl.UNSIGNED_INT, src.quads * 6 * 4);
      gl.enable(gl.DEPTH_TEST);
      gl.depthMask(true);
    }
    gl.uniform1f(this.warp.u.uW, 1.0);
    gl.drawElements(gl.TRIANGLES, src.quads * 6, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
  }

  // The in-between frame at camera `cam` (Warper::warpPair + compose).
  inBetween(cam, fg, bg) {
    const gl = this.gl, w = this.view.width, h = this.view.height;
    const vp = new Float32Array(mul(projectionMatrix(this.view), viewMatrix(cam)));
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.layerFbo);
    gl.viewport(0, 0, w, h);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.depthMask(true);
    gl.colorMask(true, true, true, true);
    gl.clearColor(0, 0, 0, 0);
    gl.clearDepth(1);
    gl.clearStencil(0);
    gl.stencilMask(0xff);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT | gl.STENCIL_BUFFER_BIT);
    // Foreground: every pixel it writes gets stencil 1.
    gl.enable(gl.STENCIL_TEST);
    gl.stencilFunc(gl.ALWAYS, 1, 0xff);
    gl.stencilOp(gl.KEEP, gl.KEEP, gl.REPLACE);
    this.drawSource(fg, vp);
    if (bg) {  // only where the foreground left pixels empty, its own depth test
      gl.stencilMask(0x00);
      gl.stencilFunc(gl.EQUAL, 0, 0xff);
      gl.stencilOp(gl.KEEP, gl.KEEP, gl.KEEP);
      gl.clear(gl.DEPTH_BUFFER_BIT);
      this.drawSource(bg, vp);
    }
    gl.disable(gl.STENCIL_TEST);
    gl.disable(gl.DEPTH_TEST);
    // Compose with the previous frame into the other frame buffer.
    const next = 1 - this.cur;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo[next]);
    gl.useProgram(this.compose.p);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.layerTex);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.frameTex[this.cur]);
    gl.uniform1i(this.compose.u.uLayer, 0);
    gl.uniform1i(this.compose.u.uPrev, 1);
    gl.uniform1i(this.compose.u.uHasPrev, this.havePrev ? 1 : 0);
    gl.bindVertexArray(this.emptyVao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.activeTexture(gl.TEXTURE0);
    this.cur = next;
    this.havePrev = true;
  }

  showKeyframe(src) {
    const gl = this.gl;
    const next = 1 - this.cur;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo[next]);
    gl.viewport(0, 0, this.view.width, this.view.height);
    gl.disable(gl.DEPTH_TEST);
    gl.disable(gl.STENCIL_TEST);
    gl.useProgram(this.key.p);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, src.tex);
    gl.uniform1i(this.key.u.uKey, 0);
    gl.uniform1i(this.key.u.uHeight, this.view.height);
    gl.bindVertexArray(this.emptyVao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    this.cur = next;
    this.havePrev = true;
  }

  present() {
    const gl = this.gl, w = this.view.width, h = this.view.height;
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, this.frameFbo[this.cur]);
    gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
    gl.blitFramebuffer(0, 0, w, h, 0, 0, w, h, gl.COLOR_BUFFER_BIT, gl.NEAREST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  // The last frame's RGBA, row 0 = top (as the native frames/NNNN.png).
  read() {
    const gl = this.gl, w = this.view.width, h = this.view.height;
    const px = new Uint8Array(w * h * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo[this.cur]);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const out = new Uint8Array(w * h * 4), row = w * 4;
    for (let y = 0; y < h; ++y) out.set(px.subarray((h - 1 - y) * row, (h - y) * row), y * row);
    return out;
  }

  sync() {  // waits for the GPU (a one-pixel read)
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.frameFbo[this.cur]);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, this.onePixel || (this.onePixel = new Uint8Array(4)));
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }
}

// ---- the player -----------------------------------------------------------

class Player {
  constructor(m, warper, sources) {
    this.m = m;
    this.w = warper;
    this.sources = sources;  // by keyframe index
    this.keyFrames = m.keyframes.map((k) => k.frame);
    this.last = -1;          // path frame in frameTex[cur], -1 = none / off the path
    this.frame = 0;
    this.lastMs = 0;
    this.used = [];
  }
  // Index into keyframes of the last keyframe at or before frame f.
  bracket(f) {
    let i = 0;
    while (i + 1 < this.keyFrames.length && this.keyFrames[i + 1] <= f) ++i;
    return i;
  }
  // Frame f of the path, exactly as the native walk draws it: the previous
  // frame is frame f − 1, so a jump replays from the bracketing keyframe.
  renderPathFrame(f) {
    if (this.last === f) return;
    const i = this.bracket(f);
    if (this.keyFrames[i] === f) {
      this.w.showKeyframe(this.sources[i]);
      this.used = [f];
    } else {
      if (this.last !== f - 1) {
        this.w.showKeyframe(this.sources[i]);
        for (let g = this.keyFrames[i] + 1; g < f; ++g) this.drawBetween(this.m.frames[g], i);
      }
      this.drawBetween(this.m.frames[f], i);
    }
    this.last = f;
    this.frame = f;
  }
  drawBetween(cam, i) {
    const ka = this.m.keyframes[i], kb = this.m.keyframes[i + 1];
    const pick = chooseForeground(cam.eye, ka.eye, kb.eye);
    const fg = pick === 0 ? i : i + 1, bg = pick === 0 ? i + 1 : i;
    this.w.inBetween(cam, this.sources[fg], this.sources[bg]);
    this.used = [this.m.keyframes[fg].frame, this.m.keyframes[bg].frame];
  }
  // Off the path: the keyframes of the nearest path frame, the last frame behind.
  renderFree(cam) {
    let best = 0, bestD = Infinity;
    this.m.frames.forEach((f, j) => { const d = sub(f.eye, cam.eye); const dd = dot(d, d); if (dd < bestD) { bestD = dd; best = j; } });
    const i = Math.min(this.bracket(best), this.keyFrames.length - 2);
    if (this.keyFrames.length < 2) this.w.showKeyframe(this.sources[0]);
    else this.drawBetween(cam, i);
    this.last = -1;
  }
}

function lookCamera(base, yaw, pitch, eye) {
  // Yaw about the path camera's up, then pitch about the new right.
  const rot = (v, axis, a) => {
    const c = Math.cos(a), s = Math.sin(a), k = dot(axis, v), x = cross(axis, v);
    return [0, 1, 2].map((j) => v[j] * c + x[j] * s + axis[j] * k * (1 - c));
  };
  let fwd = rot(base.forward, base.up, yaw), right = rot(base.right, base.up, yaw);
  fwd = norm(rot(fwd, right, pitch));
  const up = norm(cross(right, fwd));
  return { eye, right: norm(right), up, forward: fwd };
}

async function main() {
  const errorBox = document.getElementById('error');
  const hud = document.getElementById('hud');
  const canvas = document.getElementById('view');
  let resolveReady, rejectReady;
  window.hwReady = new Promise((res, rej) => { resolveReady = res; rejectReady = rej; });
  window.hwReady.catch(() => {});
  try {
    const manifestBytes = await fetchBytes('manifest.json');
    const meta = document.querySelector('meta[name="hybridwalk-manifest"]');
    const [wantBytes, wantSum] = (meta ? meta.content : '').split(' ');
    if (!/^[0-9]+$/.test(wantBytes || '') || !/^[0-9a-f]{8}$/.test(wantSum || ''))
      throw new LoadError('index.html: no manifest size and checksum (expected the page hybridwalk publish writes)');
    checkFile({ file: 'manifest.json', bytes: Number(wantBytes), checksum: wantSum }, manifestBytes, 'index.html');
    const text = new TextDecoder().decode(manifestBytes);
    let m;
    try {
      m = JSON.parse(text);
    } catch (e) {
      throw new LoadError(`manifest.json: not valid JSON (${e.message}); expected the manifest 'hybridwalk publish' writes (truncated?)`);
    }
    checkManifest(m);
    canvas.width = m.width;
    canvas.height = m.height;
    const scale = Math.max(1, Math.floor(Math.min(960 / m.width, 720 / m.height)));
    canvas.style.width = `${m.width * scale}px`;
    canvas.style.height = `${m.height * scale}px`;
    const gl = canvas.getContext('webgl2', { antialias: false, depth: false, stencil: false, alpha: false,
                                             preserveDrawingBuffer: true });
    if (!gl) throw new LoadError('this browser has no WebGL 2 (needed to warp the keyframes)');
    const warper = new Warper(gl, m);
    const files = await Promise.all(m.keyframes.map(async (k) => {
      const [png, mesh] = await Promise.all([fetchBytes(k.colour.file), fetchBytes(k.mesh.file)]);
      checkFile(k.colour, png);
      checkFile(k.mesh, mesh);
      const parsed = parseMesh(k.mesh, mesh);
      let bitmap;
      try {
        bitmap = await createImageBitmap(new Blob([png], { type: 'image/png' }),
                                         { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
      } catch (e) {
        throw new LoadError(`${k.colour.file}: not a decodable PNG (${e.message})`);
      }
      if (bitmap.width !== m.width || bitmap.height !== m.height)
        throw new LoadError(`${k.colour.file}: ${bitmap.width}x${bitmap.height} pixels, expected ${m.width}x${m.height}`);
      return { parsed, bitmap };
    }));
    const sources = files.map((f) => warper.upload(f.parsed, f.bitmap));
    const player = new Player(m, warper, sources);
    setUpUi(m, player, warper, canvas, hud);
    // Test hooks (tests/web): frame f as RGBA (row 0 = top), base64.
    window.hwRender = (f) => {
      player.renderPathFrame(f);
      warper.present();
      const px = warper.read();
      let s = '';
      for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
      return btoa(s);
    };
    // Median ms of the in-between frames of the path, drawn in order (each
    // waits for the GPU), and of the keyframe frames.
    window.hwTime = (rounds) => {
      const between = [], keys = [];
      for (let r = 0; r < (rounds || 1); ++r)
        for (let f = 0; f < m.frames.length; ++f) {
          const t0 = performance.now();
          player.renderPathFrame(f);
          warper.sync();
          (player.keyFrames.includes(f) ? keys : between).push(performance.now() - t0);
        }
      const med = (a) => { const s = [...a].sort((x, y) => x - y); return s.length ? s[Math.floor(s.length / 2)] : null; };
      const p95 = (a) => { const s = [...a].sort((x, y) => x - y); return s.length ? s[Math.min(s.length - 1, Math.floor(0.95 * s.length))] : null; };
      return { in_between_median_ms: med(between), in_between_p95_ms: p95(between), in_between_frames: between.length,
               keyframe_median_ms: med(keys), renderer: gl.getParameter(gl.RENDERER) };
    };
    resolveReady({ frames: m.frames.length, keyframes: m.keyframes.length, width: m.width, height: m.height });
  } catch (e) {
    const msg = e instanceof LoadError ? e.message : `internal error: ${e.stack || e}`;
    errorBox.textContent = `Cannot play this walkthrough: ${msg}`;
    errorBox.hidden = false;
    document.getElementById('wrap').hidden = true;
    document.getElementById('controls').hidden = true;
    window.hwError = msg;
    rejectReady(new Error(msg));
  }
}

function setUpUi(m, player, warper, canvas, hud) {
  const scrub = document.getElementById('scrub');
  const playBtn = document.getElementById('play');
  const label = document.getElementById('frameLabel');
  const params = new URLSearchParams(location.search);
  scrub.max = String(m.frames.length - 1);
  let playing = params.get('play') !== '0';
  let free = null;  // {base, eye, yaw, pitch} while flying off the path
  let dirty = true;
  const keys = new Set();
  const start = Number(params.get('frame') || 0);
  player.frame = Math.min(m.frames.length - 1, Math.max(0, Number.isInteger(start) ? start : 0));
  playBtn.textContent = playing ? 'Pause' : 'Play';
  const setPlaying = (p) => { playing = p; playBtn.textContent = p ? 'Pause' : 'Play'; };
  playBtn.onclick = () => { if (free) { free = null; } setPlaying(!playing); dirty = true; };
  scrub.oninput = () => { free = null; setPlaying(false); player.frame = Number(scrub.value); dirty = true; };
  const scene = m.scene_extent || 1;
  const goFree = () => {
    if (!free) { const c = m.frames[player.frame]; free = { base: c, eye: [...c.eye], yaw: 0, pitch: 0 }; setPlaying(false); }
  };
  window.addEventListener('keydown', (e) => {
    if (e.target === scrub) return;
    const k = e.key.toLowerCase();
    if (k === ' ') { free = null; dirty = true; e.preventDefault(); return; }
    if (k === 'p') { free = null; setPlaying(!playing); dirty = true; return; }
    if (!free && (k === 'arrowright' || k === 'arrowleft')) {
      setPlaying(false);
      player.frame = Math.min(m.frames.length - 1, Math.max(0, player.frame + (k === 'arrowright' ? 1 : -1)));
      dirty = true;
      e.preventDefault();
      return;
    }
    keys.add(k);
    if (e.shiftKey) keys.add('shift');
  });
  window.addEventListener('keyup', (e) => { keys.delete(e.key.toLowerCase()); if (!e.shiftKey) keys.delete('shift'); });
  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('mousedown', (e) => { drag = [e.clientX, e.clientY]; goFree(); canvas.focus(); });
  window.addEventListener('mouseup', () => { drag = null; });
  window.addEventListener('mousemove', (e) => {
    if (!drag || !free) return;
    free.yaw -= (e.clientX - drag[0]) * 0.004;
    free.pitch = Math.max(-1.4, Math.min(1.4, free.pitch - (e.clientY - drag[1]) * 0.004));
    drag = [e.clientX, e.clientY];
    dirty = true;
  });
  // Speed: the path's median step between frames per frame of flying.
  const steps = m.frames.slice(1).map((f, i) => Math.sqrt(dot(sub(f.eye, m.frames[i].eye), sub(f.eye, m.frames[i].eye))));
  steps.sort((a, b) => a - b);
  const step = (steps.length ? steps[Math.floor(steps.length / 2)] : 0.05 * scene) || 0.05;
  let lastTick = 0;
  const tick = (now) => {
    requestAnimationFrame(tick);
    const moves = { w: [0, 0, 1], s: [0, 0, -1], d: [1, 0, 0], a: [-1, 0, 0], e: [0, 1, 0], q: [0, -1, 0],
                    arrowup: [0, 0, 1], arrowdown: [0, 0, -1], arrowright: [1, 0, 0], arrowleft: [-1, 0, 0],
                    pageup: [0, 1, 0], pagedown: [0, -1, 0] };
    const mv = [0, 0, 0];
    for (const k of keys) if (moves[k]) for (let j = 0; j < 3; ++j) mv[j] += moves[k][j];
    if (mv.some((v) => v !== 0)) goFree();
    if (free && mv.some((v) => v !== 0)) {
      const c = lookCamera(free.base, free.yaw, free.pitch, free.eye);
      const sp = step * (keys.has('shift') ? 4 : 1);
      for (let j = 0; j < 3; ++j) free.eye[j] += sp * (mv[0] * c.right[j] + mv[1] * c.up[j] + mv[2] * c.forward[j]);
      dirty = true;
    }
    if (playing && !free && now - lastTick >= 1000 / 30) {
      lastTick = now;
      player.frame = (player.frame + 1) % m.frames.length;
      dirty = true;
    }
    if (!dirty) return;
    dirty = false;
    const t0 = performance.now();
    if (free) player.renderFree(lookCamera(free.base, free.yaw, free.pitch, free.eye));
    else player.renderPathFrame(player.frame);
    warper.present();
    warper.sync();
    const ms = performance.now() - t0;
    scrub.value = String(player.frame);
    label.textContent = free ? 'flying (space: back to the path)' : `frame ${player.frame} / ${m.frames.length - 1}`;
    hud.textContent = `${free ? 'off the path' : `frame ${player.frame}`}  ${m.width}x${m.height}\n` +
      `keyframes ${player.used.length === 1 ? `${player.used[0]} (shown)` : `${player.used[0]} (front), ${player.used[1]}`}\n` +
      `frame ${ms.toFixed(1)} ms`;
  };
  requestAnimationFrame(tick);
}

main();
