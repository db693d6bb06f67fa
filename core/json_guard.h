#pragma once
// JSON from outside, parsed defensively: nesting depth is pre-scanned before
// any parser (ours, nlohmann's or Assimp's) sees the text, and a key given
// twice in one object is an error instead of silently taking the last value.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/result.h"

namespace hw {

// Deepest array/object nesting any of our JSON inputs needs is under 10; 64
// leaves room and keeps every recursive consumer (dump(), Assimp's glTF
// reader) far from the stack limit.
inline constexpr int kMaxJsonDepth = 64;

// Error when `text` nests arrays/objects deeper than `maxDepth`, naming the
// byte where the limit is crossed. Strings (with escapes) are skipped; the
// text need not be valid JSON otherwise. Linear time, no allocation.
Status checkJsonNesting(std::string_view text, const std::string& source,
                        int maxDepth = kMaxJsonDepth);

// checkJsonNesting, then nlohmann::json::parse. Errors:
//   "SOURCE: invalid JSON at byte N: <parser message>"
//   "SOURCE: KEY.PATH: duplicate key (each key may appear once in an object; got it twice)"
Result<nlohmann::json> parseJsonStrict(std::string_view text, const std::string& source,
                                       int maxDepth = kMaxJsonDepth);

}  // namespace hw
