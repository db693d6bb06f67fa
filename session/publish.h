#pragma once
// Publishing a baked walkthrough as a static web folder: index.html, the
// player (web/player.js, embedded at build time), manifest.json (every
// frame's camera, the keyframes, the database's checksum), each keyframe's
// colour as PNG and its quad mesh as the warper's vertex data
// (warp/warp_vertices.h), so a browser warps the keyframes in WebGL 2 as the
// native program does (Zheng et al. 1999 §2). Format: docs/publish.md.
#include <cstdint>
#include <string>

#include "core/result.h"

namespace hw::session {

inline constexpr const char* kPublishFormat = "hybridwalk-web";
inline constexpr int kPublishVersion = 1;
inline constexpr char kWebMeshMagic[8] = {'H', 'W', 'W', 'E', 'B', 'M', 'S', 'H'};
inline constexpr std::size_t kWebMeshHeaderBytes = 24;

struct PublishOptions {
  std::string dbDir;   // the keyframe database (hybridwalk bake)
  std::string outDir;  // created; earlier published files in it are replaced
  // The camera path the database was baked from; empty = the default path of
  // the scene it names. Either way its hash must be the database's.
  std::string pathFile;
};

struct PublishResult {
  int frames = 0, keyframes = 0, width = 0, height = 0;
  std::uint64_t bytes = 0;  // every file written
  std::string scene;
};

// hw32 of the published files (docs/publish.md): cheap in JavaScript.
// h = 2166136261; for each 32-bit little-endian word w (the tail
// zero-padded) h = (h ^ w) · 16777619 mod 2^32; then h ^= byte length mod 2^32.
std::uint32_t hw32(const void* data, std::size_t bytes);

// Reads every keyframe of the database (each checked as `walk --keyframes`
// checks it: sizes, checksums, cameras against the path) and writes the
// folder. Errors: a database or path that fails a check, an unwritable folder.
Result<PublishResult> publish(const PublishOptions& options);

// The embedded page files (web/index.html, web/player.js).
const char* webIndexHtml();
const char* webPlayerJs();

}  // namespace hw::session
