#pragma once
// Outdoor real scenes by name or file: TORCS race tracks (scenes/ac3d.h,
// scenes/torcs_road.h, scenes/torcs_track.h) and MORSE environments
// (scenes/blend.h), with their default camera paths. The loader's hooks.
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "scenes/ac3d.h"
#include "scenes/blend.h"
#include "scenes/camera_path.h"
#include "scenes/default_paths.h"
#include "scenes/scene.h"
#include "scenes/terrain_walk.h"
#include "scenes/torcs_road.h"
#include "scenes/triangle_grid.h"

namespace hw::scenes {

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

}  // namespace hw::scenes
