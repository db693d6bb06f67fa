// libFuzzer target for the JSON pre-scan (core/json_guard.h): on any bytes
// it must agree with the parser about nesting. When nlohmann accepts the
// text, the deepest level its callback reports must exceed the limit exactly
// when checkJsonNesting refuses the text; duplicate keys must be reported.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string_view>
#include <vector>

#include "core/json_guard.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using Json = nlohmann::json;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  constexpr int kLimit = 8;
  const bool prescanOk = hw::checkJsonNesting(text, "fuzz.json", kLimit).ok();
  int deepest = 0;
  bool duplicate = false;
  std::vector<std::set<std::string>> keys;
  Json::parser_callback_t cb = [&](int depth, Json::parse_event_t ev, Json& parsed) {
    if (ev == Json::parse_event_t::object_start || ev == Json::parse_event_t::array_start) {
      deepest = std::max(deepest, depth + 1);
      keys.emplace_back();
    } else if (ev == Json::parse_event_t::object_end || ev == Json::parse_event_t::array_end) {
      if (!keys.empty()) keys.pop_back();
    } else if (ev == Json::parse_event_t::key && !keys.empty() && parsed.is_string()) {
      duplicate |= !keys.back().insert(parsed.get<std::string>()).second;
    }
    return true;
  };
  bool parsed = true;
  try {
    (void)Json::parse(text.begin(), text.end(), cb);
  } catch (const Json::exception&) {
    parsed = false;
  }
  // nlohmann stops at a NUL byte and accepts what came before; the pre-scan
  // reads the whole text, so the two only describe the same text without NULs.
  if (text.find('\0') != std::string_view::npos) parsed = false;
  if (parsed && prescanOk != (deepest <= kLimit)) {
    std::fprintf(stderr, "json_guard_fuzz: pre-scan %s, parser depth %d\n",
                 prescanOk ? "passed" : "refused", deepest);
    std::abort();
  }
  auto strict = hw::parseJsonStrict(text, "fuzz.json", kLimit);
  if (parsed && prescanOk && strict.ok() == duplicate) {
    std::fprintf(stderr, "json_guard_fuzz: duplicate key %s\n", duplicate ? "missed" : "invented");
    std::abort();
  }
  return 0;
}
