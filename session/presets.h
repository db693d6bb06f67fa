#pragma once
// The walk's presets: the one place where the program's defaults are set.
//  - Default: the settings measured best over many scenes (docs/defaults.md):
//    frames drawn as geometry or warped, whichever is cheaper (FrameMode::Auto);
//    a physical LOD threshold (parallax pixels, the same meaning on every
//    scene); region-local planarity with strip merging; keyframes built ahead
//    on a worker thread.
//  - Paper: Zheng et al. 1999 exactly: every frame warped, τ = 2^11 z' units,
//    the five-point stencil, overlay composition, no merging, no near
//    geometry, no subdivision, keyframes built when needed.
// WalkOptions{} itself is the paper's pipeline (what studies vary from).
#include <string>

#include "session/walk.h"

namespace hw::session {

enum class Preset { Default, Paper };
const char* presetName(Preset p);                      // "default", "paper"
bool parsePreset(const std::string& s, Preset* out);  // false: not a preset name

// The complete walk options of a preset (output, size and path untouched).
WalkOptions presetOptions(Preset p);

// The first setting of `o` that differs from the paper's, as the option
// that sets it (e.g. "--merge-strips") and what the paper has; empty when `o`
// is the paper's. The LOD threshold τ is not compared (a τ sweep of the
// paper's pipeline is a study of the paper).
struct PresetConflict {
  std::string option, paperValue;
};
PresetConflict differenceFromPaper(const WalkOptions& o);

}  // namespace hw::session
