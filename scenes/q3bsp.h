#pragma once
// Quake 3 / OpenArena maps (IBSP version 46) read from .pk3 (zip) files:
// polygon and mesh faces, biquadratic Bézier patches tessellated on the CPU,
// shader textures resolved as the game does, player spawns as cameras.
// Format reference: id Software, Quake III Arena GPL source (qfiles.h,
// tr_bsp.c, tr_curve.c); "Unofficial Quake 3 Map Specs" (Proudfoot, 2000).
#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/image.h"
#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::scenes {

// Quake units (≈ inches) to metres. Quake's world is Z-up; ours is Y-up:
// a point (x, y, z) becomes (x, z, −y) · kQ3MetresPerUnit (a rotation, so
// handedness and windings are preserved by the axis change itself).
inline constexpr double kQ3MetresPerUnit = 0.0254;

struct Q3Options {
  // Segments per edge of each 3×3 Bézier patch: a patch of (w−1)/2 × (h−1)/2
  // biquadratic pieces gives 2·L² triangles per piece. Clamped to [1, 64].
  int patchSubdivisions = 8;
  // .pk3 files in load order (the game's: alphabetical, later ones override
  // earlier files of the same name). Used by loadQ3Map/listQ3Maps/q3Spawns.
  std::vector<std::string> pk3Paths;
  // Faces are grouped into meshes per (material, cube of this size) so that
  // frustum culling has something to cull. In Quake units (512 ≈ 13 m).
  double chunkSizeUnits = 512.0;
  // Eye above a spawn point's origin, Quake units. The spawn origin is the
  // player's origin (24 units above the feet); DEFAULT_VIEWHEIGHT is 26, so
  // the eye is 50 units (1.27 m) above the floor, as in the game.
  double eyeHeightUnits = 26.0;
  // Refuse maps whose tessellation would exceed this (corrupt patch sizes).
  std::size_t maxTriangles = 20'000'000;
};

// A player start (info_player_deathmatch / info_player_start), in our Y-up
// metres: eye at origin + eyeHeightUnits, looking along the entity's yaw.
struct Q3Spawn {
  std::string classname;
  glm::dvec3 origin{0.0};  // entity origin, metres, Y-up
  glm::dvec3 eye{0.0};
  glm::dvec3 forward{1.0, 0.0, 0.0};  // unit, horizontal
  double yawDegrees = 0.0;            // Quake "angle": 0 = +X, counter-clockwise seen from above
  CameraKey key() const { return {eye, eye + forward}; }
};

// What a shader name resolves to. `image` empty → the loader uses a
// placeholder and reports `error` (or a generic message) in Scene::warnings.
struct Q3Texture {
  Image<Rgba8> image;
  std::string path;  // the file the image came from, for names and messages
  // The image is the one an earlier call returned for `path` (left empty
  // here: each decoded texture is kept once, by the scene).
  bool sameAsEarlier = false;
  std::string error;
  bool twoSided = false;   // shader "cull none/disable/twosided"
  bool alphaTest = false;  // shader "alphaFunc"
  float alphaCutoff = 0.5f;
  glm::vec2 uvScale{1.0f};  // the drawn stage's "tcMod scale"
};
using Q3TextureResolver = std::function<Q3Texture(const std::string& shaderName)>;

struct Q3Stats {
  std::size_t faces = 0;         // all faces in the file
  std::size_t patches = 0;       // type-2 faces tessellated
  std::size_t skippedFaces = 0;  // nodraw/fog/clip/trigger/caulk, billboards, sky without an image
  std::size_t skyFaces = 0;      // sky faces drawn (unlit) with their shader's image
  std::size_t missingTextures = 0;
  // Polygon/mesh triangles whose front (after reversing Quake's clockwise
  // order) faces away from their vertex normals; ≈ 0 for a sane map.
  std::size_t windingDisagreements = 0;
};

struct Q3Map {
  Scene scene;  // metres, Y-up, counter-clockwise front faces
  std::vector<Q3Spawn> spawns;
  Q3Stats stats;
};

// Parses an IBSP v46 file held in `bytes`. `source` names it in messages
// ("pak1-maps.pk3:maps/oa_dm5.bsp"). Nothing in the file is trusted: the
// header, every lump's offset/length/element size, face texture, vertex and
// meshvert ranges, meshvert indices, patch dimensions (odd, ≥ 3, matching
// the vertex count), finite positions and the entity text are checked, and
// a violation is an error naming `source`, the lump (and face), expected vs
// got. `resolve` is asked once per used shader; null → all placeholders.
Result<Q3Map> parseQ3Bsp(std::string_view bytes, const std::string& source,
                         const Q3TextureResolver& resolve, const Q3Options& options = {});

// Player spawns from an entities lump's text (also used by parseQ3Bsp).
Result<std::vector<Q3Spawn>> parseQ3Spawns(std::string_view entities, const std::string& source,
                                           const Q3Options& options = {});

// Loads maps/<mapName>.bsp (case-insensitive) from options.pk3Paths, with
// textures from the same pk3s: a shader script's first image stage (with its
// "tcMod scale"), for a sky shader its cloud stage or else its skyParms box's
// top image ("_up"), else the shader name + ".tga", then + ".jpg". Sky faces
// are drawn unlit with that image on the sky brushes (not as a box at
// infinity). The shader features of the map's shaders that are not drawn
// (blended further stages, tcMod scroll/rotate/turb/stretch, tcGen
// environment, deformVertexes, rgbGen/alphaGen, animMap animation,
// lightmaps) are listed in one Scene::warnings line. Errors name the pk3/entry: unreadable,
// not a zip, truncated, missing map (listing the maps that do exist).
Result<Q3Map> loadQ3Map(const std::string& mapName, const Q3Options& options);

// A walk at eye height through the spawns, each first stood on the surface
// below it (spawns may float; the game drops the player): from the spawn
// that starts the longest chain (ties: the one whose first view sees the
// least sky/void), each next key is the nearest unvisited spawn in clear
// line of sight of the previous one (the segment between their eyes hits no
// triangle), up to `maxKeys` keys; each key looks towards the next, level,
// or up to 15° down where looking level sees mostly sky or void.
// Catmull-Rom as CameraPath does; 120 frames, a keyframe every 10, near
// 0.05 m, far from the map's size. A map whose spawns see no other spawn
// walks 2 m forward from its first spawn; a map without spawns gets
// flythroughPathFor(scene).
CameraPath q3SpawnWalk(const Q3Map& map, int maxKeys = 8);

// Names of all maps/<name>.bsp in the pk3s, sorted, without duplicates.
Result<std::vector<std::string>> listQ3Maps(const std::vector<std::string>& pk3Paths);

// The map's spawns only (reads just the BSP's entities lump).
Result<std::vector<Q3Spawn>> q3Spawns(const std::string& mapName, const Q3Options& options);

// One scripts/*.shader text as the map loader reads it: how many shaders it
// defines, and a warning naming `where` and the line for a malformed file
// (its remaining shaders are ignored), empty when well-formed. For tests and
// the fuzz target; never fails otherwise.
struct Q3ShaderScriptSummary {
  std::size_t shaders = 0;
  std::string warning;
};
Q3ShaderScriptSummary summarizeQ3ShaderScript(std::string_view text, const std::string& where);

}  // namespace hw::scenes
