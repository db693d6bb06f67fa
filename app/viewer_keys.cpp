// The viewer's keys, scripted keys and statistics levels (app/viewer_keys.h).
#include "app/viewer_keys.h"

#include <cctype>
#include <cstdio>

namespace hw::app {

const std::vector<ViewerKey>& viewerKeys() {
  static const std::vector<ViewerKey> keys = {
      {"s", "statistics",
       "statistics: fps / + per-stage ms, quads, holes / + keyframe stalls / off"},
      {"w", "wireframe/quad outlines", "wireframe (hybrid: warped quad outlines)"},
      {"f", "full screen", "full screen"},
      {"c", "screenshot", "screenshot (PNG in the current directory)"},
      {"z", "record path", "record a camera path (again: stop and save)"},
      {"Z", "play path", "play the recorded path (again: stop)"},
      {"space", "home", "home"},
      {"Esc", "quit", "quit"},
      {"h", "help", "this help"},
      {"g", "hybrid/geometry", "hybrid / geometry rendering"},
      {"o", "overlay", "quad overlay of the foreground keyframe"},
      {"m", "hole mask", "hole mask (red: no keyframe covers)"},
      {"p", "PSNR", "PSNR against the geometry reference"},
  };
  return keys;
}

std::string viewerKeyHelp() {
  std::string out =
      "hybridwalk viewer keys\n"
      "  right mouse held: mouse look, W/A/S/D fly, Q/E down/up\n"
      "  arrows, PageUp/PageDown: move   Shift: x4   + / -: speed\n";
  char line[160];
  for (const ViewerKey& k : viewerKeys()) {
    std::snprintf(line, sizeof line, "  %-6s %s\n", k.key, k.help);
    out += line;
  }
  return out;
}

std::string viewerKeyLine() {
  std::string out;
  for (const ViewerKey& k : viewerKeys()) {
    if (!out.empty()) out += ", ";
    out += std::string(k.key) + " " + k.brief;
  }
  return out;
}

Result<std::vector<ScriptedKey>> parseScriptedKeys(const std::string& text) {
  std::vector<ScriptedKey> out;
  long frame = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c != '@') {
      out.push_back({frame, c});
      continue;
    }
    std::size_t j = i + 1;
    long n = 0;
    while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) && n < 1000000000L)
      n = n * 10 + (text[j++] - '0');
    if (j == i + 1 || (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j]))))
      return makeError("keys '" + text + "': '@' at character " + std::to_string(i + 1) +
                       " must be followed by a frame number below 10^9 (e.g. 's@30p': p before "
                       "frame 30)");
    if (n < frame)
      return makeError("keys '" + text + "': frame marks must not decrease, got @" +
                       std::to_string(n) + " after @" + std::to_string(frame));
    frame = n;
    i = j - 1;
  }
  return out;
}

StatsLevel nextStatsLevel(StatsLevel level) {
  return static_cast<StatsLevel>((static_cast<int>(level) + 1) % 4);
}

const char* statsLevelDescription(StatsLevel level) {
  switch (level) {
    case StatsLevel::Off:
      return "statistics off";
    case StatsLevel::Fps:
      return "statistics: fps";
    case StatsLevel::Stages:
      return "statistics: fps, per-stage ms, quads, holes";
    case StatsLevel::Stalls:
      return "statistics: fps, per-stage ms, quads, holes, keyframe stalls and waits";
  }
  return "statistics";
}

}  // namespace hw::app
