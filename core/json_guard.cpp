#include "core/json_guard.h"

#include <set>
#include <vector>

namespace hw {

Status checkJsonNesting(std::string_view text, const std::string& source, int maxDepth) {
  int depth = 0;
  bool inString = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\')
        ++i;  // skip the escaped character (\" does not end the string)
      else if (c == '"')
        inString = false;
      continue;
    }
    if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth)
        return makeError(source + ": JSON nested deeper than " + std::to_string(maxDepth) +
                         " levels at byte " + std::to_string(i + 1) + " (expected at most " +
                         std::to_string(maxDepth) + " levels of arrays/objects)");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return {};
}

namespace {

struct Level {
  bool isArray = false;
  std::size_t index = 0;
  std::string key;
  std::set<std::string> keys;
};

std::string pathOf(const std::vector<Level>& stack, const std::string& lastKey) {
  std::string p;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    const Level& l = stack[i];
    const bool last = i + 1 == stack.size();
    if (l.isArray) {
      p += '[';
      p += std::to_string(l.index);
      p += ']';
    } else {
      if (!p.empty()) p += '.';
      const std::string& k = last ? lastKey : l.key;
      p += k.empty() ? std::string("\"\"") : k;  // the empty key, visible
    }
  }
  return p;
}

}  // namespace

Result<nlohmann::json> parseJsonStrict(std::string_view text, const std::string& source,
                                       int maxDepth) {
  HW_TRY(checkJsonNesting(text, source, maxDepth));
  using Json = nlohmann::json;
  std::vector<Level> stack;
  bool haveDuplicate = false;
  std::string duplicate;  // path of the first repeated key
  auto elementDone = [&] {
    if (!stack.empty() && stack.back().isArray) ++stack.back().index;
  };
  Json::parser_callback_t cb = [&](int, Json::parse_event_t ev, Json& parsed) {
    switch (ev) {
      case Json::parse_event_t::object_start: stack.push_back(Level{}); break;
      case Json::parse_event_t::array_start: stack.push_back(Level{true, 0, {}, {}}); break;
      case Json::parse_event_t::key: {
        if (stack.empty()) break;
        const std::string k = parsed.is_string() ? parsed.get<std::string>() : parsed.dump();
        if (!stack.back().keys.insert(k).second && !haveDuplicate) {
          haveDuplicate = true;
          duplicate = pathOf(stack, k);
        }
        stack.back().key = k;
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        if (!stack.empty()) stack.pop_back();
        elementDone();
        break;
      case Json::parse_event_t::value: elementDone(); break;
    }
    return true;
  };
  Json root;
  try {
    root = Json::parse(text.begin(), text.end(), cb);
  } catch (const Json::parse_error& e) {
    return makeError(source + ": invalid JSON at byte " + std::to_string(e.byte) + ": " + e.what());
  } catch (const Json::exception& e) {
    return makeError(source + ": invalid JSON: " + e.what());
  }
  if (haveDuplicate)
    return makeError(source + ": " + duplicate +
                     ": duplicate key (each key may appear once in an object; got it twice, and "
                     "which one counts would be a guess)");
  return root;
}

}  // namespace hw
