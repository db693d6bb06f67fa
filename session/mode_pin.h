#pragma once
// Auto's choices, pinned per walk. `--mode auto` decides per keyframe segment
// from costs measured while it runs, so a segment whose warp costs about the
// threshold goes either way in two runs of one command. A measured walk
// writes how each of its frames was drawn to a pin file named by a hash of
// everything the choice depends on (scene, cameras, schedule, options,
// machine, build); a later walk with the same hash draws each frame the
// same way instead of choosing again. File format: docs/mode-pins.md.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "session/frame_mode.h"

namespace hw::session {

// WalkOptions::autoPin (`--auto-pin`).
enum class AutoPin {
  Use,      // replay the pin that matches this walk; none: choose, then write one
  Measure,  // choose from this run's costs, then write the pin (replacing one)
  Off,      // choose from this run's costs; read and write no pin
};
const char* autoPinName(AutoPin p);  // "use", "measure", "off"

// 64-bit FNV-1a over what is fed, in order.
class PinHasher {
 public:
  void bytes(const void* p, std::size_t n);
  void text(std::string_view s);  // its length, then its bytes
  void number(double v) { bytes(&v, sizeof v); }
  void number(std::int64_t v) { bytes(&v, sizeof v); }
  std::uint64_t value() const { return h_; }
  std::string hex() const;  // 16 lower-case hex digits

 private:
  std::uint64_t h_ = 14695981039346656037ull;
};

// Where pins are kept: $HYBRIDWALK_PINS, else $XDG_CACHE_HOME/hybridwalk/
// mode-pins, else $HOME/.cache/hybridwalk/mode-pins; "" when none is set.
std::string defaultModePinDir();

// One letter per frame kind in a pin: g(eometry), w(arp), k(eyframe).
char frameKindLetter(FrameKind k);

// What a pin holds: how each frame was drawn and how many rectangles each
// frame's hole pass drew (its budget follows the measured geometry cost, so
// a replay that chose again would draw other pixels); -1 where none ran.
// holeRects empty: not pinned (a pin written before it was kept).
struct ModePin {
  std::vector<FrameKind> kinds;
  std::vector<int> holeRects;
};

// Reads the pin `file` for a walk of `frames` frames. *found = false (and no
// error) when there is no such file. Errors (what, where, expected vs got):
// unreadable, not a pin, another format version or frame count, a letter
// other than g, w, k, hole rectangles that are not one integer >= -1 per frame.
Result<ModePin> readModePin(const std::string& file, int frames, bool* found);
// Writes the pin atomically (creating its folder), one entry per frame in
// each list (holeRects empty or as long as kinds), with `label` (the scene)
// and the time it was measured.
Status writeModePin(const std::string& file, const ModePin& pin, const std::string& label);

}  // namespace hw::session
