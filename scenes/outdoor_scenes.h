#pragma once
// Outdoor real scenes: TORCS race tracks (AC3D .acc, our own parser) and
// MORSE environments (Blender .blend through Assimp, SkyBox hidden), plus the
// geometric queries their camera paths need (ground height, clearance).
// AC3D reference: Inivis, "AC3D file format" (ac3d.org/ac3d/man/ac3dfileformat.html);
// TORCS extensions as read by TORCS' grloadac.cpp (multi-layer `texture`
// lines, SURF type 4 = triangle strip, 6-number vertices with normals).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "scenes/scene.h"

namespace hw::scenes {

// ---------------------------------------------------------------- AC3D / TORCS

struct Ac3dOptions {
  // Folders searched for textures after the model's own folder, in order
  // (TORCS: data/textures, data/img of the install). loadTorcsTrack fills them.
  std::vector<std::string> textureDirs;
  // Triangles are grouped into meshes per (material, square cell of this
  // size on the ground plane), in the file's units (metres for TORCS), so
  // that frustum culling has something to cull. ≤ 0: one mesh per material.
  double chunkSizeMetres = 200.0;
  // Alpha cut-off of textures whose name contains "tree", "trans-" or
  // "arbor" (TORCS' own rule, grloadac.cpp); other textures with
  // transparent texels (alpha < 128) use Material::alphaCutoff's 0.5.
  float foliageAlphaCutoff = 0.65f;
};

struct Ac3dStats {
  std::size_t objects = 0;              // OBJECT blocks, all types
  std::size_t surfaces = 0;             // SURF records, all types
  std::size_t lineSurfaces = 0;         // types 1/2 (lines), skipped
  std::size_t twoSidedSurfaces = 0;     // SURF flag 0x20
  std::size_t multiLayerObjects = 0;    // objects naming more than the base texture layer
  std::size_t degenerateTriangles = 0;  // repeated index or zero area: dropped
  std::size_t missingTextures = 0;      // replaced by a checker (see Scene::warnings)
};

struct Ac3dModel {
  Scene scene;  // Y-up as AC3D is; counter-clockwise front faces; uv v = 0 at the image top
  Ac3dStats stats;
  // Per material: the base texture's file name as written in the file ("" for none).
  std::vector<std::string> materialTextureNames;
};

// Parses AC3D text (`source` names it in messages, `folder` is where its
// textures are looked for first). Object hierarchies are flattened with
// `loc` (parent frame) and `rot` (9 numbers, row i = image of axis i, as
// plib reads them). Of a TORCS object's texture layers only the base one
// (`texture NAME base`, or a plain `texture NAME`) is used; `tiled`,
// `skids` and `shad` layers are ignored, as are extra uv pairs in refs.
// Polygons are fans, type-4 surfaces strips; degenerate triangles are
// dropped. SURF flag 0x20 → Material::twoSided. Textures: PNG/JPG/TGA via
// stb, SGI .rgb/.rgba/.sgi/.bw by our own decoder; a missing or unreadable
// texture becomes a checker plus a warning. Errors (not AC3D, truncated
// blocks, out-of-range indices, malformed numbers, no triangles) give
// source:line and what was expected. Never throws.
Result<Ac3dModel> parseAc3d(const std::string& text, const std::string& source,
                            const std::string& folder, const Ac3dOptions& options = {});
Result<Ac3dModel> loadAc3dFile(const std::string& path, const Ac3dOptions& options = {});

// A TORCS track file (tracks/CATEGORY/NAME/NAME.acc) with TORCS' texture
// search path (the track folder, then data/textures and data/img of the
// install the track belongs to).
Result<Ac3dModel> loadTorcsTrack(const std::string& accPath);

// Finds tracks/*/NAME/NAME.acc under `root` (searched recursively for a
// `tracks` folder, e.g. CACHE/root/usr/share/games/torcs). Error lists the
// tracks found when NAME is not one of them.
Result<std::string> findTorcsTrack(const std::string& root, const std::string& name);

// Decodes an SGI image (.rgb/.rgba/.bw: 1–4 channels, 8 bits, verbatim or
// RLE). Grey → RGB, missing alpha → 255; row 0 = top. Errors name `what`.
Result<Image<Rgba8>> decodeSgiImage(const std::string& bytes, const std::string& what);

// ---------------------------------------------------------------- MORSE / Blender

struct BlendOptions {
  // Nodes with these names are left out with all their children.
  std::vector<std::string> hiddenNodes{"SkyBox"};
  // Nodes whose names start with these lose their own meshes but keep their
  // children: MORSE's "BB_" objects are invisible collision boxes that
  // parent the visible tree (Tree.001 → BB_Trunk.001 → Plane-Tree.001).
  std::vector<std::string> hiddenNodePrefixes{"BB_"};
  bool zUp = true;                // Blender is Z-up: (x, y, z) → (x, z, −y)
  double chunkSizeMetres = 25.0;  // as Ac3dOptions::chunkSizeMetres
};

// A .blend through Assimp's Blender importer with node transforms applied
// and hidden nodes dropped. Blender procedural textures (Assimp names them
// "Procedural,...") cannot be evaluated: those materials use their diffuse
// colour. Embedded (packed) images are decoded; all materials are
// two-sided (Blender draws both sides by default). Never throws; Assimp's
// error text is quoted.
Result<Scene> loadBlendFile(const std::string& path, const BlendOptions& options = {});

// ---------------------------------------------------------------- specs

// "torcs:NAME" (a track in the scene cache) or "morse:ENV/FILE" (FILE.blend
// in morse/data/environments/ENV of the cache): the file it names, or an
// error saying what was looked for (and that `hybridwalk scenes fetch
// --outdoor` provides it). nullopt when `spec` is neither form.
std::optional<Result<std::string>> outdoorSpecFile(const std::string& spec,
                                                   const std::string& cacheDir);

// Loads a .acc (as a TORCS track when it sits in a tracks/ tree) or .blend
// file. nullopt when the extension is neither.
std::optional<Result<Scene>> loadOutdoorFile(const std::string& path);

// The hooks of loader.cpp: an existing .acc/.blend file, "torcs:NAME" or
// "morse:ENV/FILE" (in defaultSceneCacheDir()). nullopt: not ours.
std::optional<Result<Scene>> loadOutdoorSpec(const std::string& spec);
// Their default paths: for tracks torcsDefaultPath (scenes/torcs_track.h:
// the track description's centreline, else drivePath's trace); for .blend
// scenes a floorWalkPath at 1.7 m (scenes/floor_walk.h), else (no floor
// found, with a note) a terrainWalkPath around a circle of 0.25 × the
// smaller ground extent.
std::optional<Result<CameraPath>> outdoorDefaultPath(const std::string& spec,
                                                     const DefaultPathOptions& options = {},
                                                     std::vector<std::string>* notes = nullptr);

// ---------------------------------------------------------------- queries

// Uniform grid over a scene's triangles (world space) for ground-height,
// clearance and ray queries; brute force inside cells. Sky surfaces
// (Material::sky) are left out. Built once, read-only after.
class TriangleGrid {
 public:
  explicit TriangleGrid(const Scene& scene, double cellSize = 2.0);

  // Heights (Y) of every surface hit by a ray straight down (−Y) from
  // `from`, highest first.
  std::vector<double> hitsBelow(const glm::dvec3& from) const;
  // Distance from `p` to the nearest triangle, or `maxDistance` when none is
  // closer than that.
  double distanceToNearest(const glm::dvec3& p, double maxDistance) const;
  // True when the segment a→b stays at least `clearance` from every
  // triangle (checked at steps of clearance/2).
  bool segmentClear(const glm::dvec3& a, const glm::dvec3& b, double clearance) const;
  // Distance along the unit direction `dir` from `origin` to the first
  // triangle hit (either side), or nullopt when none is within maxDistance.
  std::optional<double> rayHit(const glm::dvec3& origin, const glm::dvec3& dir,
                               double maxDistance) const;

  std::size_t triangleCount() const { return tris_.size(); }

 private:
  struct Tri {
    glm::dvec3 a, b, c;
  };
  glm::ivec3 cellOf(const glm::dvec3& p) const;
  const std::vector<std::uint32_t>* cell(const glm::ivec3& c) const;

  std::vector<Tri> tris_;
  glm::dvec3 origin_{0.0};
  glm::ivec3 dims_{0};
  double cellSize_;
  std::vector<std::vector<std::uint32_t>> cells_;
};

// Where an eye stands: the drop to the first surface straight below it
// (nullopt: nothing below, the eye is over the void) and the distance to
// the nearest triangle (capped at maxClearance; ~0: inside a wall).
struct EyeCheck {
  std::optional<double> floorDrop;
  double clearance = 0.0;
  // Above a floor within maxDrop and at least minClearance from every surface.
  bool playable(double maxDrop, double minClearance) const {
    return floorDrop && *floorDrop <= maxDrop && clearance >= minClearance;
  }
};
EyeCheck checkEye(const TriangleGrid& grid, const glm::dvec3& eye, double maxClearance = 1.0);

// The fraction of a view that sees nothing within maxDistance (sky or void):
// rays through an n × n grid of pixel centres of a camera at `eye` looking
// along `forward` (up +Y, square image, vertical field of view fovYDeg).
double openViewFraction(const TriangleGrid& grid, const glm::dvec3& eye, const glm::dvec3& forward,
                        double fovYDeg, double maxDistance, int n = 16);

// Distance from p to triangle abc (Ericson, Real-Time Collision Detection §5.1.5).
double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c);

// ---------------------------------------------------------------- paths

struct DrivePathOptions {
  // Road triangles: those whose material's base texture name (file stem,
  // case-insensitive) starts with one of these (forza: Road, Road-crack1,
  // ROADSF_n start line, ROADPL_n pit lane).
  std::vector<std::string> roadTextureStems{"road"};
  double stepMetres = 4.0;        // centreline sample spacing
  double eyeHeightMetres = 1.2;   // above the road surface
  double lookAheadMetres = 12.0;  // look-at point this far along the centreline
  double startMetres = 0.0;       // where along the loop the path starts
  double lengthMetres = 450.0;    // how much of the loop it drives (≤ loop length)
  // Speed in metres per frame; > 0 overrides lengthMetres: the path drives
  // metresPerFrame × (frames − 1) metres (at most one loop).
  double metresPerFrame = 0.0;
  bool reverse = false;           // drive the loop the other way (needs a closed trace)
  // roadCentreline stops once it has traced this much (drivePath asks for
  // what it drives); a closed loop ends earlier.
  double traceMetres = 1e9;
  int frames = 240;
  int keyframeEvery = 10;
};

// The road's centreline (Y on the road surface), traced from the road point
// nearest the road's centroid by marching through uniformly sampled road
// points: each step moves `stepMetres` ahead and re-centres on the middle of
// the road's cross-section there (gaps of other textures bridged, sideways
// shift per step limited, areas wider than a road crossed straight). Stops
// when it closes (*closed = true) or has traced options.traceMetres. Error
// when no road texture is found or the road is lost before traceMetres.
Result<std::vector<glm::dvec3>> roadCentreline(const Ac3dModel& track,
                                               const DrivePathOptions& options = {},
                                               bool* closed = nullptr);
// A camera path driving `lengthMetres` of the centreline from `startMetres`:
// 512², fov 60°, near 0.5 m, far 1000 m, one key per `stepMetres`.
Result<CameraPath> drivePath(const Ac3dModel& track, const DrivePathOptions& options = {});

struct TerrainWalkOptions {
  double eyeHeightMetres = 1.7;   // above the ground found by ray casting down
  double keySpacingMetres = 4.0;  // keys placed along the polyline at this spacing
  double lookAheadMetres = 8.0;
  int frames = 240;
  int keyframeEvery = 10;
};

// A walk through `waypointsXZ` (x, z ground positions, polyline) at eye
// height above the LOWEST surface below each key (the terrain, not the tree
// canopies over it). Error when a key has no ground below it. 512², fov 60°,
// near 0.1 m, far 1000 m.
Result<CameraPath> terrainWalkPath(const TriangleGrid& grid,
                                   const std::vector<glm::dvec2>& waypointsXZ,
                                   const TerrainWalkOptions& options = {});

}  // namespace hw::scenes
