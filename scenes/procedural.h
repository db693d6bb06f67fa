#pragma once
// Built-in procedural scenes for controlled experiments: an indoor building
// (rooms, doorways, corridor, furniture) and an outdoor terrain (hills,
// buildings, trees). One knob scales the triangle count without changing the look.
#include <cstddef>

#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::scenes {

// Indoor scene, metres, Y up, about 33 m × 24 m × 3 m: four rooms either side
// of a corridor that opens into a hall, doorways 1.2 m × 2.2 m, tables, crates,
// columns and spheres, procedural brick/tile/checker/wood textures.
// `targetTriangles` (clamped to [5'000, 50'000'000]) sets the tessellation
// density of every surface; the result is within about ±10% of the target for
// targets ≥ 10'000 (the scene has a floor of a few thousand triangles).
// Geometry is split into spatial chunks of one material each. Deterministic.
Scene makeIndoorScene(std::size_t targetTriangles);

// Outdoor scene, metres, Y up, 320 m × 320 m terrain of gentle hills (heights
// about ±10 m), 30-ish buildings with window textures, conifers (cones) and
// broad-leaved trees (alpha-tested two-sided crowns). Same knob and guarantees
// as makeIndoorScene. No sky geometry: the renderer clears to skyColour.
Scene makeOutdoorScene(std::size_t targetTriangles);

// Ground height of the outdoor terrain at (x, z), metres (the exact surface
// the terrain mesh samples; the mesh interpolates it linearly).
double outdoorTerrainHeight(double x, double z);

// A walk at eye height 1.7 m from the south-west room through its doorway,
// along the corridor and into the hall; 512×512, fov 60°, near 0.1, far 100,
// 120 frames, a keyframe every 10. Clear of walls and furniture.
CameraPath defaultIndoorPath();

// A drive about 4 m above the outdoor terrain along a lane kept free of
// buildings and trees; 512×512, fov 60°, near 0.5, far 1000, 120 frames,
// a keyframe every 10.
CameraPath defaultOutdoorPath();

}  // namespace hw::scenes
