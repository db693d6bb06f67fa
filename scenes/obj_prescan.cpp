#include "scenes/obj_prescan.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace hw::scenes {

Result<ObjCounts> countObjElements(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return makeError(path + ": cannot open: " + std::strerror(errno));
  ObjCounts c;
  std::vector<char> buf(1 << 20);
  // Per-line state: column (0 = line start), the line's kind, and whether
  // the previous character was a separator (a new token starts after it).
  int col = 0;
  char kind0 = 0;
  bool face = false, inToken = false;
  std::string mLine;  // the current line, when it starts with 'm' (mtllib)
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) {
    for (std::size_t i = 0; i < n; ++i) {
      const char ch = buf[i];
      if (ch == '\n' || ch == '\r') {
        if (kind0 == 'm' && col > 0 && mLine.rfind("mtllib", 0) == 0 && c.mtllibs.size() < 16) {
          std::string name = mLine.substr(6);
          const auto b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t");
          if (b != std::string::npos && (mLine[6] == ' ' || mLine[6] == '\t'))
            c.mtllibs.push_back(name.substr(b, e - b + 1));
        }
        mLine.clear();
        col = 0;
        face = false;
        inToken = false;
        continue;
      }
      if (col == 0) kind0 = ch;
      if (kind0 == 'm' && mLine.size() < 4096) mLine += ch;
      else if (col == 1) {
        const bool sep = ch == ' ' || ch == '\t';
        if (kind0 == 'v' && sep) ++c.vertices;
        if (kind0 == 'f' && sep) {
          ++c.faces;
          face = true;
        }
      }
      ++col;
      if (face && col > 2) {
        const bool sep = ch == ' ' || ch == '\t';
        if (!sep && !inToken) ++c.references;
        inToken = !sep;
      }
    }
  }
  if (kind0 == 'm' && col > 6 && mLine.rfind("mtllib", 0) == 0 && c.mtllibs.size() < 16 &&
      (mLine[6] == ' ' || mLine[6] == '\t')) {
    const auto b = mLine.find_first_not_of(" \t", 6), e = mLine.find_last_not_of(" \t");
    if (b != std::string::npos) c.mtllibs.push_back(mLine.substr(b, e - b + 1));
  }
  const bool bad = std::ferror(f);
  std::fclose(f);
  if (bad) return makeError(path + ": read error");
  return c;
}

std::uint64_t objImportBytes(const ObjCounts& c) { return c.references * 200 + c.vertices * 100; }

}  // namespace hw::scenes
