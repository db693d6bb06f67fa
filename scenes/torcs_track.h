#pragma once
// A TORCS track's own description (tracks/CATEGORY/NAME/NAME.xml, TORCS'
// "params" XML): the main track as straights and left/right arcs, integrated
// into its centreline as TORCS' track loader does (track4.cpp CreateSegRing:
// right edge starts at (0, 0), left edge at (0, width), heading +x; arcs'
// radius is the centreline's; an arc with an end radius is split into steps
// of equal length whose radius changes linearly). TORCS then shifts the whole
// track so that its bounding box starts at 0, so the centreline is registered
// against the track model's vertices before it is driven (torcsDrivePath).
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/torcs_road.h"

namespace hw::scenes {

struct TorcsSegment {
  enum class Kind { Straight, Left, Right };
  std::string name;  // the segment's section name in the file
  int line = 0;      // where its section starts (1-based)
  Kind kind = Kind::Straight;
  double lengthMetres = 0.0;      // straights
  double radiusMetres = 0.0;      // arcs: the centreline's radius at the start
  double endRadiusMetres = 0.0;   // arcs: at the end (= radius unless "end radius")
  double arcRadians = 0.0;        // arcs, > 0 for both directions
  int profileSteps = 0;           // "profil steps" (0: from the step length)
  double profileStepMetres = -1;  // "profil steps length" (< 0: the track's)
  // Length along the centreline (an arc: mean radius × arc).
  double centreLength() const;
};

struct TorcsTrackDescription {
  std::string source;  // the file, for messages
  std::string name, category;
  double widthMetres = 15.0;       // Main Track "width" (TORCS' default 15 m)
  double profileStepMetres = 0.0;  // Main Track "profil steps length" (0: none)
  std::vector<TorcsSegment> segments;
  double lengthMetres() const;  // sum of the segments' centreLength()
};

// Parses a TORCS track description. Values are converted from their `unit`
// (m, cm, mm, km, ft, in, deg, rad, %) to metres/radians. Errors name
// `source`, the line and the segment: not XML (unclosed or mismatched tags,
// attributes without quotes), no "Main Track" section or no segments in it, a
// segment without a type or of an unknown one, a straight without a positive
// "lg", an arc without a positive "radius" and "arc", a number that is not
// one, an unknown unit. Never throws.
Result<TorcsTrackDescription> parseTorcsTrackXml(std::string_view text, const std::string& source);
Result<TorcsTrackDescription> loadTorcsTrackXml(const std::string& path);

// tracks/C/N/N.acc → tracks/C/N/N.xml ("" when `accPath` is not so named).
std::string torcsDescriptionPathFor(const std::string& accPath);

struct TorcsCentrelineOptions {
  double sampleMetres = 1.0;  // spacing of the output points along the centreline
  // A track closes when its end is within this of its start and its end
  // heading within closeDegrees of its start heading.
  double closeMetres = 5.0;
  double closeDegrees = 5.0;
};

struct TorcsCentreline {
  // TORCS' ground plane (x, y), metres, before TORCS' shift to positive
  // coordinates; points[0] = (0, width/2), the start line's centre.
  std::vector<glm::dvec2> points;  // one per sampleMetres, the end (= start) not repeated
  std::vector<double> arcLength;   // of each point, from the start
  std::vector<int> segment;        // index into the description's segments
  double lengthMetres = 0.0;       // of the whole loop
  // Both edges at every step boundary TORCS' loader creates (where the
  // track model has vertices), for registration.
  std::vector<glm::dvec2> edgePoints;
  double closureGapMetres = 0.0;  // |end − start| before closing
  double closureDegrees = 0.0;    // |end heading − start heading|, wrapped
};

// Integrates the main track. Error (naming the file and the last segment)
// when it does not close within the options' tolerance.
Result<TorcsCentreline> integrateTorcsCentreline(const TorcsTrackDescription& track,
                                                 const TorcsCentrelineOptions& options = {});

// Where TORCS put the centreline in the model: model (x, y, z) = (x·1,
// height, zSign·y) + (offset.x, ·, offset.y), Y-up as parseAc3d reads it.
struct TorcsRegistration {
  double zSign = -1.0;  // TORCS' y → model −z (AC3D's Y-up axes), or +z
  glm::dvec2 offset{0.0};
  double matchedFraction = 0.0;  // of edgePoints with a model vertex within 0.2 m
  glm::dvec3 toModel(const glm::dvec2& p, double height) const {
    return {p.x + offset.x, height, zSign * p.y + offset.y};
  }
};

// Finds the translation (and z mirror) that puts the centreline's edge
// points onto the model's vertices: candidates from vertices near the
// first edge points, scored by how many edge points land within 0.2 m of a
// vertex. Error when fewer than `minMatched` of them do.
Result<TorcsRegistration> registerTorcsCentreline(const TorcsCentreline& line, const Scene& model,
                                                  double minMatched = 0.5);

// Drives the centreline at options.eyeHeightMetres above the road surface
// found in the model (ray cast down; the surface nearest the previous
// sample's, so bridges and tunnels keep to the road). Speed: options.metresPerFrame
// (0: lengthMetres over frames); starts at the start line + startMetres;
// looks at the road lookAheadMetres ahead, a quarter of the eye height above
// it; 512², fov 60°, near 0.5 m, far 1000 m, a key every stepMetres.
Result<CameraPath> torcsDrivePath(const Ac3dModel& track, const TorcsCentreline& line,
                                  const TorcsRegistration& reg,
                                  const DrivePathOptions& options = {});

// The default path of a TORCS track file: from its description when
// NAME.xml is beside it (errors in it are errors), else roadCentreline's
// trace (and a note saying so in *notes).
Result<CameraPath> torcsDefaultPath(const std::string& accPath, const DrivePathOptions& options,
                                    std::vector<std::string>* notes);

}  // namespace hw::scenes
