#pragma once
// The viewer's command keys in one table, from which the `h` help and the
// key list of `view --help` are written (DESIGN.md "Viewer conventions");
// scripted keys (`view --keys`, with frame marks); the statistics levels
// that `s` cycles through. Plain data, no GL.
#include <string>
#include <vector>

#include "core/result.h"

namespace hw::app {

struct ViewerKey {
  const char* key;    // as typed ("space" and "Esc" by name)
  const char* brief;  // a few words, for `view --help`
  const char* help;   // one line, for `h`
};

// Every command key, in the order `h` lists them.
const std::vector<ViewerKey>& viewerKeys();

// The text `h` prints and shows: the movement controls, then one line per key.
std::string viewerKeyHelp();

// "g hybrid/geometry, w wireframe/quad outlines, ..., Esc quit": every key of
// viewerKeys(), for `view --help`.
std::string viewerKeyLine();

// A key typed before frame `frame` (0: before the first) of a scripted session.
struct ScriptedKey {
  long frame = 0;
  unsigned key = 0;
};

// `--keys` text: each character is a key press; "@N" (N a whole number)
// types the keys after it before frame N instead, e.g. "s@30p@60p": `s`
// before the first frame, `p` before frames 30 and 60. Frame marks must not
// decrease. An error names the text and what was expected.
Result<std::vector<ScriptedKey>> parseScriptedKeys(const std::string& text);

// What `s` shows: nothing, the frame rate, then per-stage ms, quads and
// holes, then also the keyframe stalls and waits; `s` goes to the next level
// and from the last back to off. The viewer starts at Fps.
enum class StatsLevel { Off = 0, Fps = 1, Stages = 2, Stalls = 3 };
StatsLevel nextStatsLevel(StatsLevel level);
const char* statsLevelDescription(StatsLevel level);  // printed when `s` is pressed

}  // namespace hw::app
