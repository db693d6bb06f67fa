#pragma once
// TORCS tracks as AC3D models: finding and loading one, and the drive along
// its road traced from the model's road textures (the fallback when the
// track's own description is missing; scenes/torcs_track.h).
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "scenes/ac3d.h"
#include "scenes/camera_path.h"

namespace hw::scenes {

// A TORCS track file (tracks/CATEGORY/NAME/NAME.acc) with TORCS' texture
// search path (the track folder, then data/textures and data/img of the
// install the track belongs to).
Result<Ac3dModel> loadTorcsTrack(const std::string& accPath);

// Finds tracks/*/NAME/NAME.acc under `root` (searched recursively for a
// `tracks` folder, e.g. CACHE/root/usr/share/games/torcs). Error lists the
// tracks found when NAME is not one of them.
Result<std::string> findTorcsTrack(const std::string& root, const std::string& name);

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

}  // namespace hw::scenes
