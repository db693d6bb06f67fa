#pragma once
// Keyframe database: baked keyframes (camera, colour, z', eye z, coverage) and
// their quad meshes (Zheng et al. 1999 §1.1–1.2) on disk, one checksummed file
// per keyframe plus index.json, so a walk can read keyframes instead of
// rendering them. Format: docs/keyframe-db.md. CPU only.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "keyframe/keyframe_cache.h"

namespace hw::keyframe {

inline constexpr char kKeyframeFileMagic[8] = {'H', 'W', 'K', 'F', 'R', 'A', 'M', 'E'};
inline constexpr std::uint32_t kKeyframeFormatVersion = 1;
inline constexpr std::size_t kKeyframeHeaderBytes = 64;
inline constexpr const char* kKeyframeDbFormat = "hybridwalk-keyframe-db";
inline constexpr int kKeyframeDbVersion = 1;

// hw64: the 64-bit checksum of the format (docs/keyframe-db.md). Words of 8
// little-endian bytes (the tail zero-padded), each mixed in as
// h = rotl(h ^ w, 31) * 0x9E3779B97F4A7C15, then the length, then the
// splitmix64 finaliser. Detects every single flipped byte; not cryptographic.
std::uint64_t hw64(const void* data, std::size_t bytes, std::uint64_t seed = 0x6877646232303236ull);
std::string hex64(std::uint64_t v);  // 16 lower-case hex digits

// One keyframe file's bytes: header + payload. Timings (render, Δ, subdivide,
// corner ms) are not stored, so equal inputs give bit-identical files.
std::string encodeKeyframe(int frame, const Keyframe& keyframe, const QuadMesh& mesh,
                           const RenderStats& render);
// Parses and checks `bytes` (magic, version, sizes, header and payload
// checksums, frame, ranges). `file` names the file in error messages. On
// success fills out.frame/keyframe/mesh/render; timings are zero.
Status decodeKeyframe(std::string_view bytes, const std::string& file, CachedKeyframe& out);
// Header checksum of the payload without reading the payload (for the index).
Result<std::uint64_t> keyframeFileChecksum(std::string_view headerBytes, const std::string& file);

std::string keyframeFileName(int frame);  // "kf_000123.hwkf"

// What a database was baked from; a reader compares it field by field.
struct KeyframeDbProvenance {
  std::string scene;          // --scene label as given
  std::size_t triangles = 0;  // scene triangle count
  std::string pathHash;       // hw64 of the camera path's canonical JSON (hex)
  int frames = 0;             // frames of the walk (after --frames)
  int width = 0, height = 0;
  std::string depthMode;  // depthModeName
  nlohmann::json
      mesh;  // {"method","tau","tau_px","criterion","planarity","merge_strips","merge_tolerance"}
             // plus "tau_gradient" when > 0 (meshOptionsJson)
};
nlohmann::json meshOptionsJson(const LodOptions& lod);
nlohmann::json provenanceJson(const KeyframeDbProvenance& p);

struct KeyframeDbEntry {
  int frame = 0;
  std::string file;  // relative to the database directory
  std::uint64_t bytes = 0;
  std::uint64_t checksum = 0;  // payload hw64, as in the file header
};

// index.json text of a database (entries sorted by frame).
std::string keyframeDbIndexJson(const KeyframeDbProvenance& p,
                                const std::vector<KeyframeDbEntry>& entries);

// What a walk expects of every keyframe it reads from a database: the camera
// of that frame on its own path (which fixes size, projection and pose) and
// its depth mode. A database whose index was edited consistently (entries
// swapped in from another path, or baked at another size) passes every
// checksum; this catches it when the keyframe is read.
struct KeyframeExpectation {
  std::function<Camera(int frame)> cameraAt;
  std::optional<DepthMode> depthMode;  // unset: any (the viewer takes the database's)
};
// Error naming the first camera field, size or depth mode that differs.
Status checkKeyframeExpectation(const CachedKeyframe& kf, const KeyframeExpectation& want,
                                const std::string& file);

// Entries of index.json's "keyframes" array (or a chunk result's "entries"):
// each {frame: 0..2^31-1, file: plain name, bytes, checksum: 16 hex digits};
// frames unique. `source` names the file in messages.
Result<std::vector<KeyframeDbEntry>> parseKeyframeEntries(const nlohmann::json& entries,
                                                          const std::string& source);

// hw64 of index.json's content without its "index_checksum" member (compact
// dump, keys sorted): the value stored in "index_checksum".
std::string indexChecksum(const nlohmann::json& index);

class KeyframeDb {
 public:
  // Reads and checks DIR/index.json (format, version, entries). Keyframe
  // files are checked when read.
  static Result<KeyframeDb> open(const std::string& dir);
  // Error naming the first field that differs (scene, path, frames, size,
  // depth mode, mesh options), with the database's value and the expected one.
  // `fields` (provenance JSON keys: "scene", "triangles", "path_hash",
  // "frames", "resolution", "depth_mode", "mesh") limits the comparison;
  // empty compares all.
  Status checkMatches(const KeyframeDbProvenance& expected,
                      const std::vector<std::string>& fields = {}) const;
  const std::vector<KeyframeDbEntry>& entries() const { return entries_; }
  std::vector<int> keyframeFrames() const;
  const nlohmann::json& index() const { return index_; }
  const std::string& dir() const { return dir_; }
  // Error unless the database holds keyframes for exactly `frames` (the walk's
  // schedule), naming the first frame missing or extra.
  Status checkSchedule(const std::vector<int>& frames) const;
  // The whole database against index.json and the expectation (if set), before
  // the first frame and whatever the walk's mode: every keyframe file's header
  // (magic, version, header checksum, frame, size) and its camera block are
  // read, not the payload: the file's size and payload checksum must be
  // index.json's, the camera and depth mode the walk's. Error naming the first
  // file that differs. (A payload damaged under an intact header is caught
  // when that keyframe is read.)
  Status checkFiles() const;
  // Every keyframe read from now on is checked against `want`.
  void setExpectation(KeyframeExpectation want) {
    expect_ = std::make_shared<const KeyframeExpectation>(std::move(want));
  }
  // Reads, checks (size and checksum against the index too) and decodes the
  // keyframe of `frame`. Safe to call from several threads.
  Status read(int frame, CachedKeyframe& out) const;

 private:
  std::shared_ptr<const KeyframeExpectation> expect_;
  std::string dir_;
  nlohmann::json index_;
  std::vector<KeyframeDbEntry> entries_;
};

// A KeyframeCache::Source over `db`. With `prefetch`, after handing out the
// keyframe of frame k it decodes the next keyframe of the database on one
// background thread (file read, checksum, decode: CPU only; GL uploads stay
// with the caller), so a walk along the path rarely waits for the disk.
// CachedKeyframe::renderMs is the time the call took (wait + read + decode);
// the mesh build timings are zero (not stored). `hits`, if given, counts the
// calls served by a prefetch.
KeyframeCache::Source makeKeyframeDbSource(std::shared_ptr<const KeyframeDb> db,
                                           bool prefetch = true,
                                           std::shared_ptr<std::size_t> hits = nullptr);

}  // namespace hw::keyframe
