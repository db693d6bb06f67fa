// TORCS track descriptions: a small reader for TORCS' params XML, the
// centreline integration of track4.cpp's CreateSegRing, registration against
// the model's vertices and the drive along it. See torcs_track.h.
#include "scenes/torcs_track.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "core/file_io.h"
#include "core/short_number.h"
#include "scenes/triangle_grid.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// ------------------------------------------------------------ params XML

struct XmlAttr {
  std::string name, val, unit;
  int line = 0;
};

struct XmlSection {
  std::string name;
  int line = 0;
  std::vector<XmlAttr> attrs;  // attnum / attstr children, in order
  std::vector<XmlSection> sections;

  const XmlSection* child(std::string_view n) const {
    for (const XmlSection& s : sections)
      if (s.name == n) return &s;
    return nullptr;
  }
  const XmlAttr* attr(std::string_view n) const {
    for (const XmlAttr& a : attrs)
      if (a.name == n) return &a;
    return nullptr;
  }
};

constexpr int kMaxXmlDepth = 64;

// Just enough XML for TORCS' params files: elements with quoted attributes,
// comments, <?…?>, <!DOCTYPE …[…]>, CDATA and text (ignored). Only
// <section>, <attnum> and <attstr> are kept; other elements are walked
// through.
class XmlReader {
 public:
  XmlReader(std::string_view text, const std::string& source) : t_(text), source_(source) {}

  Result<XmlSection> run() {
    XmlSection root;
    root.name = "";
    std::vector<std::string> open;  // element names
    std::vector<XmlSection*> stack{&root};
    std::vector<bool> isSection;
    while (true) {
      const std::size_t lt = t_.find('<', pos_);
      countLines(lt == std::string_view::npos ? t_.size() : lt);
      if (lt == std::string_view::npos) break;
      pos_ = lt;
      if (starts("<!--")) {
        const std::size_t e = t_.find("-->", pos_ + 4);
        if (e == std::string_view::npos) return fail("comment never closed ('-->' missing)");
        advanceTo(e + 3);
        continue;
      }
      if (starts("<![CDATA[")) {
        const std::size_t e = t_.find("]]>", pos_);
        if (e == std::string_view::npos) return fail("CDATA never closed (']]>' missing)");
        advanceTo(e + 3);
        continue;
      }
      if (starts("<?")) {
        const std::size_t e = t_.find("?>", pos_);
        if (e == std::string_view::npos) return fail("'<?' never closed ('?>' missing)");
        advanceTo(e + 2);
        continue;
      }
      if (starts("<!")) {  // DOCTYPE with an optional [internal subset]
        std::size_t i = pos_ + 2;
        int bracket = 0;
        char quote = 0;
        for (; i < t_.size(); ++i) {
          const char c = t_[i];
          if (quote) {
            if (c == quote) quote = 0;
          } else if (c == '"' || c == '\'') {
            quote = c;
          } else if (c == '[') {
            ++bracket;
          } else if (c == ']') {
            --bracket;
          } else if (c == '>' && bracket <= 0) {
            break;
          }
        }
        if (i >= t_.size()) return fail("'<!' declaration never closed");
        advanceTo(i + 1);
        continue;
      }
      if (starts("</")) {
        std::size_t i = pos_ + 2;
        const std::string name = readName(&i);
        while (i < t_.size() && std::isspace(static_cast<unsigned char>(t_[i]))) ++i;
        if (i >= t_.size() || t_[i] != '>') return fail("expected '>' to end '</" + name + "'");
        if (open.empty()) return fail("closing tag '</" + name + ">' with no element open");
        if (open.back() != name)
          return fail("closing tag '</" + name + ">' where '</" + open.back() + ">' was expected");
        open.pop_back();
        if (isSection.back()) stack.pop_back();
        isSection.pop_back();
        advanceTo(i + 1);
        continue;
      }
      // Start tag.
      std::size_t i = pos_ + 1;
      const std::string name = readName(&i);
      if (name.empty()) return fail("expected an element name after '<'");
      std::vector<std::pair<std::string, std::string>> attrs;
      bool selfClosing = false;
      while (true) {
        while (i < t_.size() && std::isspace(static_cast<unsigned char>(t_[i]))) {
          if (t_[i] == '\n') ++line_;
          ++i;
        }
        if (i >= t_.size()) return fail("tag '<" + name + "' never closed (file ends)");
        if (t_[i] == '>') {
          ++i;
          break;
        }
        if (t_[i] == '/' && i + 1 < t_.size() && t_[i + 1] == '>') {
          selfClosing = true;
          i += 2;
          break;
        }
        const std::string an = readName(&i);
        if (an.empty())
          return fail("in '<" + name + "': expected an attribute name, got '" +
                      std::string(t_.substr(i, 1)) + "'");
        while (i < t_.size() && std::isspace(static_cast<unsigned char>(t_[i]))) ++i;
        if (i >= t_.size() || t_[i] != '=')
          return fail("in '<" + name + "': attribute '" + an + "' without '=\"value\"'");
        ++i;
        while (i < t_.size() && std::isspace(static_cast<unsigned char>(t_[i]))) ++i;
        if (i >= t_.size() || (t_[i] != '"' && t_[i] != '\''))
          return fail("in '<" + name + "': attribute '" + an + "' value without quotes");
        const char q = t_[i++];
        const std::size_t e = t_.find(q, i);
        if (e == std::string_view::npos)
          return fail("in '<" + name + "': attribute '" + an + "' value never closed");
        std::string v(t_.substr(i, e - i));
        for (char c : v)
          if (c == '\n') ++line_;
        attrs.emplace_back(an, unescape(v));
        i = e + 1;
      }
      const int tagLine = line_;
      auto get = [&](const char* k) -> std::string {
        for (const auto& [a, v] : attrs)
          if (a == k) return v;
        return {};
      };
      bool section = false;
      if (name == "section") {
        if (open.size() >= kMaxXmlDepth)
          return fail("sections nested deeper than " + std::to_string(kMaxXmlDepth));
        XmlSection s;
        s.name = get("name");
        s.line = tagLine;
        stack.back()->sections.push_back(std::move(s));
        if (!selfClosing) {
          stack.push_back(&stack.back()->sections.back());
          section = true;
        }
      } else if (name == "attnum" || name == "attstr") {
        XmlAttr a{get("name"), get("val"), get("unit"), tagLine};
        stack.back()->attrs.push_back(std::move(a));
      }
      if (!selfClosing) {
        if (open.size() >= kMaxXmlDepth)
          return fail("elements nested deeper than " + std::to_string(kMaxXmlDepth));
        open.push_back(name);
        isSection.push_back(section);
      }
      pos_ = i;
    }
    if (!open.empty())
      return makeError(source_ + ": file ends with '<" + open.back() +
                       ">' still open (expected '</" + open.back() + ">')");
    return root;
  }

 private:
  bool starts(std::string_view s) const { return t_.substr(pos_, s.size()) == s; }
  void countLines(std::size_t end) {
    for (std::size_t i = pos_; i < end && i < t_.size(); ++i)
      if (t_[i] == '\n') ++line_;
    pos_ = std::min(end, t_.size());
  }
  void advanceTo(std::size_t end) { countLines(end); }
  std::string readName(std::size_t* i) const {
    const std::size_t s = *i;
    while (*i < t_.size()) {
      const unsigned char c = static_cast<unsigned char>(t_[*i]);
      if (std::isalnum(c) || c == '_' || c == '-' || c == ':' || c == '.')
        ++*i;
      else
        break;
    }
    return std::string(t_.substr(s, *i - s));
  }
  static std::string unescape(const std::string& v) {
    if (v.find('&') == std::string::npos) return v;
    std::string out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i] == '&') {
        static const std::pair<const char*, char> kEnt[] = {
            {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
        bool done = false;
        for (const auto& [e, c] : kEnt)
          if (v.compare(i, std::strlen(e), e) == 0) {
            out += c;
            i += std::strlen(e) - 1;
            done = true;
            break;
          }
        if (done) continue;
      }
      out += v[i];
    }
    return out;
  }
  Error fail(const std::string& what) const {
    return makeError(source_ + ":" + std::to_string(line_) + ": not valid XML: " + what);
  }

  std::string_view t_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

// Unit factors to SI (metres, radians), as TORCS' tgf converts them.
std::optional<double> unitFactor(const std::string& unit) {
  std::string u;
  for (char c : unit) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (u.empty() || u == "m" || u == "rad" || u == "s") return 1.0;
  if (u == "deg") return kPi / 180.0;
  if (u == "km") return 1000.0;
  if (u == "cm") return 0.01;
  if (u == "mm") return 0.001;
  if (u == "ft") return 0.3048;
  if (u == "in") return 0.0254;
  if (u == "%") return 0.01;
  return std::nullopt;
}

// A number attribute of `s` in SI units; nullopt when absent.
Result<std::optional<double>> number(const XmlSection& s, const char* name,
                                     const std::string& source, const std::string& where) {
  const XmlAttr* a = s.attr(name);
  if (!a) return std::optional<double>();
  const auto f = unitFactor(a->unit);
  if (!f)
    return makeError(source + ":" + std::to_string(a->line) + ": " + where + ": '" + name +
                     "' has unknown unit '" + a->unit +
                     "' (expected m, cm, mm, km, ft, in, deg, rad or %)");
  std::string v = a->val;
  while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back()))) v.pop_back();
  std::size_t b = 0;
  while (b < v.size() && std::isspace(static_cast<unsigned char>(v[b]))) ++b;
  if (b < v.size() && v[b] == '+') ++b;
  double x = 0;
  auto [p, ec] = std::from_chars(v.data() + b, v.data() + v.size(), x);
  if (ec != std::errc() || p != v.data() + v.size() || !std::isfinite(x))
    return makeError(source + ":" + std::to_string(a->line) + ": " + where + ": '" + name +
                     "' expected a number, got '" + a->val + "'");
  return std::optional<double>(x * *f);
}

std::string str(const XmlSection& s, const char* name) {
  const XmlAttr* a = s.attr(name);
  return a ? a->val : std::string();
}

}  // namespace

double TorcsSegment::centreLength() const {
  if (kind == Kind::Straight) return lengthMetres;
  return 0.5 * (radiusMetres + endRadiusMetres) * arcRadians;
}

double TorcsTrackDescription::lengthMetres() const {
  double l = 0;
  for (const TorcsSegment& s : segments) l += s.centreLength();
  return l;
}

Result<TorcsTrackDescription> parseTorcsTrackXml(std::string_view text, const std::string& source) {
  auto rootR = XmlReader(text, source).run();
  if (!rootR) return rootR.error();
  const XmlSection& root = *rootR;
  // <params> holds the sections; the reader keeps sections only, so the
  // top-level sections are those of <params>.
  TorcsTrackDescription d;
  d.source = source;
  if (const XmlSection* h = root.child("Header")) {
    d.name = str(*h, "name");
    d.category = str(*h, "category");
  }
  const XmlSection* main = root.child("Main Track");
  if (!main)
    return makeError(source +
                     ": no <section name=\"Main Track\"> (expected a TORCS track "
                     "description with the main track's segments)");
  auto w = number(*main, "width", source, "Main Track");
  if (!w) return w.error();
  if (*w) {
    if (!(**w > 0.0 && **w < 1000.0))
      return makeError(source + ":" + std::to_string(main->attr("width")->line) +
                       ": Main Track: width expected in (0, 1000) m, got " + shortNumber(**w));
    d.widthMetres = **w;
  }
  auto step = number(*main, "profil steps length", source, "Main Track");
  if (!step) return step.error();
  if (*step) d.profileStepMetres = std::max(0.0, **step);
  // "Track Segments" (version 4), "segments" (older files).
  const XmlSection* list = nullptr;
  for (const XmlSection& c : main->sections) {
    std::string n;
    for (char ch : c.name) n += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (n == "track segments" || n == "segments") {
      list = &c;
      break;
    }
  }
  if (!list || list->sections.empty())
    return makeError(source + ":" + std::to_string(main->line) +
                     ": Main Track has no segments (expected <section name=\"Track Segments\"> "
                     "holding one section per straight or arc)");
  for (const XmlSection& s : list->sections) {
    const std::string where = "segment '" + s.name + "'";
    const std::string at = source + ":" + std::to_string(s.line) + ": " + where;
    TorcsSegment seg;
    seg.name = s.name;
    seg.line = s.line;
    const std::string type = str(s, "type");
    if (type == "str") {
      seg.kind = TorcsSegment::Kind::Straight;
    } else if (type == "lft") {
      seg.kind = TorcsSegment::Kind::Left;
    } else if (type == "rgt") {
      seg.kind = TorcsSegment::Kind::Right;
    } else {
      return makeError(at + ": type expected 'str', 'lft' or 'rgt', got " +
                       (s.attr("type") ? "'" + type + "'" : std::string("none")));
    }
    auto num = [&](const char* n) { return number(s, n, source, where); };
    if (seg.kind == TorcsSegment::Kind::Straight) {
      auto lg = num("lg");
      if (!lg) return lg.error();
      if (!*lg || !(**lg > 0.0 && **lg < 1e5))
        return makeError(at + ": a straight needs 'lg' in (0, 100000) m, got " +
                         (*lg ? shortNumber(**lg) : std::string("none")));
      seg.lengthMetres = **lg;
    } else {
      auto r = num("radius"), re = num("end radius"), arc = num("arc");
      if (!r) return r.error();
      if (!re) return re.error();
      if (!arc) return arc.error();
      if (!*r || !(**r > 0.0 && **r < 1e5))
        return makeError(at + ": an arc needs 'radius' in (0, 100000) m, got " +
                         (*r ? shortNumber(**r) : std::string("none")));
      if (!*arc || !(**arc > 0.0 && **arc <= 4 * kPi))
        return makeError(at + ": an arc needs 'arc' in (0, 720] deg, got " +
                         (*arc ? shortNumber(**arc * 180.0 / kPi) + " deg" : std::string("none")));
      seg.radiusMetres = **r;
      seg.endRadiusMetres = *re ? **re : **r;
      if (!(seg.endRadiusMetres > 0.0 && seg.endRadiusMetres < 1e5))
        return makeError(at + ": 'end radius' expected in (0, 100000) m, got " +
                         shortNumber(seg.endRadiusMetres));
      seg.arcRadians = **arc;
    }
    auto ps = num("profil steps"), psl = num("profil steps length");
    if (!ps) return ps.error();
    if (!psl) return psl.error();
    if (*ps) seg.profileSteps = static_cast<int>(std::clamp(**ps, 0.0, 10000.0));
    if (*psl) seg.profileStepMetres = std::max(0.0, **psl);
    d.segments.push_back(std::move(seg));
  }
  return d;
}

Result<TorcsTrackDescription> loadTorcsTrackXml(const std::string& path) {
  auto text = readFile(path);
  if (!text) return text.error();
  return parseTorcsTrackXml(*text, path);
}

std::string torcsDescriptionPathFor(const std::string& accPath) {
  const fs::path p(accPath);
  if (p.extension() != ".acc" || p.stem() != p.parent_path().filename()) return "";
  return (p.parent_path() / (p.stem().string() + ".xml")).string();
}

Result<TorcsCentreline> integrateTorcsCentreline(const TorcsTrackDescription& track,
                                                 const TorcsCentrelineOptions& options) {
  HW_CHECK(options.sampleMetres > 0);
  if (track.segments.empty()) return makeError(track.source + ": the main track has no segments");
  // One piece per step of TORCS' loader: a straight, or an arc of constant
  // radius about `centre`.
  struct Piece {
    int segment;
    glm::dvec2 start;
    double heading, length, radius, sign;  // sign: +1 left, −1 right, 0 straight
  };
  std::vector<Piece> pieces;
  TorcsCentreline out;
  const double wi2 = 0.5 * track.widthMetres;
  glm::dvec2 p(0.0, wi2);  // centreline at the start line
  double alf = 0.0;
  auto pointOf = [](const Piece& pc, double t) {
    const glm::dvec2 dir(std::cos(pc.heading), std::sin(pc.heading));
    if (pc.sign == 0) return pc.start + dir * t;
    const glm::dvec2 left(-std::sin(pc.heading), std::cos(pc.heading));
    const glm::dvec2 centre = pc.start + pc.sign * pc.radius * left;
    const double a = pc.heading + pc.sign * t / pc.radius;
    return centre - pc.sign * pc.radius * glm::dvec2(-std::sin(a), std::cos(a));
  };
  for (std::size_t si = 0; si < track.segments.size(); ++si) {
    const TorcsSegment& seg = track.segments[si];
    const double length = seg.centreLength();
    // TORCS' steps: "profil steps", else length / step length + 1.
    int steps = seg.profileSteps > 0 ? seg.profileSteps : 1;
    const double stepLen =
        seg.profileStepMetres >= 0 ? seg.profileStepMetres : track.profileStepMetres;
    if (steps == 1 && stepLen > 0) steps = static_cast<int>(std::min(1e5, length / stepLen)) + 1;
    double curLength = length / steps;
    double radius = seg.radiusMetres;
    double dradius = 0.0;
    if (seg.kind != TorcsSegment::Kind::Straight && seg.endRadiusMetres != seg.radiusMetres) {
      dradius = (seg.endRadiusMetres - seg.radiusMetres) / steps;
      if (steps > 1) {  // step length so that the steps' arcs add up to the arc
        dradius = (seg.endRadiusMetres - seg.radiusMetres) / (steps - 1);
        double a = 0, r = radius;
        for (int k = 0; k < steps; ++k) {
          a += curLength / r;
          r += dradius;
        }
        curLength *= seg.arcRadians / a;
      }
    }
    for (int k = 0; k < steps; ++k) {
      const glm::dvec2 left(-std::sin(alf), std::cos(alf));
      out.edgePoints.push_back(p + left * wi2);
      out.edgePoints.push_back(p - left * wi2);
      Piece pc{static_cast<int>(si), p, alf, curLength, radius, 0.0};
      if (seg.kind != TorcsSegment::Kind::Straight) {
        pc.sign = seg.kind == TorcsSegment::Kind::Left ? 1.0 : -1.0;
        const double arc = dradius != 0 ? curLength / radius : seg.arcRadians / steps;
        pc.length = radius * arc;
        alf += pc.sign * arc;
        radius += dradius;
      }
      p = pointOf(pc, pc.length);
      pieces.push_back(pc);
    }
  }
  double total = 0;
  for (const Piece& pc : pieces) total += pc.length;
  if (!(total > 0.0) || total > 1e6)
    return makeError(track.source + ": main track length " + shortNumber(total) +
                     " m (expected between 0 and 1000 km)");
  out.lengthMetres = total;
  // Closure: the end back at the start, heading back to 0 (mod 2π).
  out.closureGapMetres = glm::length(p - glm::dvec2(0.0, wi2));
  double dh = std::fmod(alf, 2 * kPi);
  if (dh > kPi) dh -= 2 * kPi;
  if (dh < -kPi) dh += 2 * kPi;
  out.closureDegrees = std::abs(dh) * 180.0 / kPi;
  if (out.closureGapMetres > options.closeMetres || out.closureDegrees > options.closeDegrees) {
    const TorcsSegment& last = track.segments.back();
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "the main track does not close: after its last segment '%s' (line %d) the "
                  "centreline ends %.1f m from the start, heading %.1f deg off (expected within "
                  "%.1f m and %.1f deg; %zu segments, %.0f m)",
                  last.name.c_str(), last.line, out.closureGapMetres, out.closureDegrees,
                  options.closeMetres, options.closeDegrees, track.segments.size(), total);
    return makeError(track.source + ": " + buf);
  }
  const std::size_t samples =
      std::max<std::size_t>(3, static_cast<std::size_t>(std::ceil(total / options.sampleMetres)));
  if (samples > 10'000'000) return makeError(track.source + ": centreline too long to sample");
  // Samples at equal spacing; the small closing gap spread along the loop so
  // that it joins smoothly.
  const glm::dvec2 gap = p - glm::dvec2(0.0, wi2);
  std::size_t pi = 0;
  double pieceStart = 0;
  for (std::size_t k = 0; k < samples; ++k) {
    const double s = total * static_cast<double>(k) / samples;
    while (pi + 1 < pieces.size() && pieceStart + pieces[pi].length <= s) {
      pieceStart += pieces[pi].length;
      ++pi;
    }
    out.points.push_back(pointOf(pieces[pi], s - pieceStart) - gap * (s / total));
    out.arcLength.push_back(s);
    out.segment.push_back(pieces[pi].segment);
  }
  return out;
}

// ------------------------------------------------------------ registration

namespace {

struct VertexHash {
  static constexpr double kCell = 0.5;
  std::unordered_map<std::int64_t, std::vector<glm::dvec2>> cells;
  static std::int64_t key(std::int64_t x, std::int64_t z) { return (x << 32) ^ (z & 0xffffffffLL); }
  void add(const glm::dvec2& p) {
    cells[key(static_cast<std::int64_t>(std::floor(p.x / kCell)),
              static_cast<std::int64_t>(std::floor(p.y / kCell)))]
        .push_back(p);
  }
  bool near(const glm::dvec2& p, double r) const {
    const auto x0 = static_cast<std::int64_t>(std::floor((p.x - r) / kCell)),
               x1 = static_cast<std::int64_t>(std::floor((p.x + r) / kCell));
    const auto z0 = static_cast<std::int64_t>(std::floor((p.y - r) / kCell)),
               z1 = static_cast<std::int64_t>(std::floor((p.y + r) / kCell));
    for (auto z = z0; z <= z1; ++z)
      for (auto x = x0; x <= x1; ++x)
        if (auto it = cells.find(key(x, z)); it != cells.end())
          for (const glm::dvec2& q : it->second)
            if (glm::dot(q - p, q - p) <= r * r) return true;
    return false;
  }
};

}  // namespace

Result<TorcsRegistration> registerTorcsCentreline(const TorcsCentreline& line, const Scene& model,
                                                  double minMatched) {
  if (line.edgePoints.empty()) return makeError(model.name + ": no centreline to register");
  constexpr double kMatch = 0.2;
  VertexHash hash;
  std::unordered_set<std::int64_t> seen;
  std::vector<glm::dvec2> verts;
  for (const Mesh& m : model.meshes)
    for (const Vertex& v : m.vertices) {
      const glm::dvec2 q(v.position.x, v.position.z);
      // Deduplicate at 1 cm: the same corner is repeated per surface.
      const std::int64_t k = VertexHash::key(static_cast<std::int64_t>(std::floor(q.x * 100)),
                                             static_cast<std::int64_t>(std::floor(q.y * 100)));
      if (seen.insert(k).second) {
        hash.add(q);
        verts.push_back(q);
      }
    }
  if (verts.empty()) return makeError(model.name + ": the model has no vertices");
  // Evenly spread probe points; candidates from the vertices near where the
  // first probe can land (anywhere in the model's bounds).
  std::vector<glm::dvec2> probe;
  const std::size_t n = line.edgePoints.size();
  const std::size_t want = std::min<std::size_t>(n, 400);
  for (std::size_t k = 0; k < want; ++k) probe.push_back(line.edgePoints[k * n / want]);
  TorcsRegistration best;
  double bestScore = -1;
  for (double zSign : {-1.0, 1.0}) {
    auto map = [&](const glm::dvec2& p) { return glm::dvec2(p.x, zSign * p.y); };
    // Candidate offsets: every vertex minus the first probe point. Score on
    // a quick subset first, then on all probes.
    const glm::dvec2 p0 = map(probe[0]);
    const std::size_t quick = std::min<std::size_t>(probe.size(), 24);
    for (const glm::dvec2& v : verts) {
      const glm::dvec2 off = v - p0;
      int hits = 0;
      for (std::size_t k = 1; k < quick; ++k)
        if (hash.near(map(probe[k]) + off, kMatch)) ++hits;
      if (hits < static_cast<int>(quick) / 3) continue;
      int all = 0;
      for (const glm::dvec2& p : probe)
        if (hash.near(map(p) + off, kMatch)) ++all;
      const double score = static_cast<double>(all) / probe.size();
      if (score > bestScore) {
        bestScore = score;
        best.zSign = zSign;
        best.offset = off;
        best.matchedFraction = score;
      }
    }
  }
  if (bestScore < minMatched) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  ": the track description's edges do not match the model's vertices (best "
                  "%.0f %% of %zu edge points within %.1f m, expected at least %.0f %%)",
                  100.0 * std::max(0.0, bestScore), probe.size(), kMatch, 100.0 * minMatched);
    return makeError(model.name + buf);
  }
  return best;
}

Result<CameraPath> torcsDrivePath(const Ac3dModel& track, const TorcsCentreline& line,
                                  const TorcsRegistration& reg, const DrivePathOptions& options) {
  if (line.points.size() < 3) return makeError(track.scene.name + ": centreline too short");
  const TriangleGrid grid(track.scene);
  const double total = line.lengthMetres;
  const int frames = std::max(1, options.frames);
  double length =
      options.metresPerFrame > 0 ? options.metresPerFrame * (frames - 1) : options.lengthMetres;
  length = std::clamp(length, 1.0, total);
  // Road height along the line: the surface below each sample nearest the
  // previous one's (starting from the highest surface within 3 m of the
  // model's vertex heights at the start line, i.e. not a gantry over it).
  const std::size_t m = line.points.size();
  std::vector<double> height(m, std::numeric_limits<double>::quiet_NaN());
  double prev = std::numeric_limits<double>::quiet_NaN();
  std::size_t missing = 0;
  const std::size_t first =
      static_cast<std::size_t>(
          std::lround(std::fmod(std::max(0.0, options.startMetres), total) / (total / m))) %
      m;
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = (first + j) % m;
    const glm::dvec3 at = reg.toModel(line.points[k], 1e6);
    const std::vector<double> hits = grid.hitsBelow(at);
    if (hits.empty()) {
      ++missing;
      continue;
    }
    double h = hits.back();
    if (std::isnan(prev)) {
      // The start: the lowest surface that has others within 3 m above it
      // is ground; take the lowest hit (road or terrain under it), then the
      // highest of the hits within 0.5 m above that (road over terrain).
      for (double y : hits)
        if (y - hits.back() < 0.5) h = std::max(h, y);
    } else {
      for (double y : hits)
        if (std::abs(y - prev) < std::abs(h - prev)) h = y;
      if (std::abs(h - prev) > 3.0) h = prev;  // a gap in the model: keep level
    }
    height[k] = h;
    prev = h;
  }
  if (missing * 10 > m)
    return makeError(track.scene.name + ": " + std::to_string(missing) + " of " +
                     std::to_string(m) +
                     " centreline samples have no surface below them: the track description "
                     "does not match the model");
  for (std::size_t j = 0; j < m; ++j) {  // fill holes from the neighbours before
    const std::size_t k = (first + j) % m;
    if (std::isnan(height[k])) height[k] = height[(k + m - 1) % m];
  }
  for (std::size_t k = 0; k < m; ++k)
    if (std::isnan(height[k])) height[k] = height[(k + 1) % m];
  // Light smoothing of the road height (kerbs, seams).
  {
    std::vector<double> sm(height);
    for (std::size_t k = 0; k < m; ++k)
      sm[k] = 0.25 * height[(k + m - 1) % m] + 0.5 * height[k] + 0.25 * height[(k + 1) % m];
    height = std::move(sm);
  }
  auto pointAt = [&](double sArc) {
    sArc = std::fmod(sArc, total);
    if (sArc < 0) sArc += total;
    const auto it = std::upper_bound(line.arcLength.begin(), line.arcLength.end(), sArc);
    const std::size_t i =
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - line.arcLength.begin() - 1));
    const std::size_t j = (i + 1) % m;
    const double s1 = j == 0 ? total : line.arcLength[j];
    const double t =
        s1 > line.arcLength[i] ? (sArc - line.arcLength[i]) / (s1 - line.arcLength[i]) : 0;
    const glm::dvec2 p = line.points[i] + (line.points[j] - line.points[i]) * t;
    const double h = height[i] + (height[j] - height[i]) * t;
    return reg.toModel(p, h);
  };
  CameraPath path;
  path.nearPlane = 0.5;
  path.farPlane = 1000.0;
  path.frames = frames;
  path.keyframeEvery = options.keyframeEvery;
  const double dir = options.reverse ? -1.0 : 1.0;
  const glm::dvec3 up(0, options.eyeHeightMetres, 0);
  // A driver looks at the road ahead: the look-at point is a quarter of the
  // eye height above it (about 4° down at 1.2 m and 12 m ahead).
  const glm::dvec3 lookUp(0, 0.25 * options.eyeHeightMetres, 0);
  const double step = std::max(0.5, options.stepMetres);
  const int keys = std::max(2, static_cast<int>(std::ceil(length / step)) + 1);
  for (int k = 0; k < keys; ++k) {
    const double sArc = options.startMetres + dir * length * k / (keys - 1);
    path.keys.push_back(
        {pointAt(sArc) + up, pointAt(sArc + dir * options.lookAheadMetres) + lookUp});
  }
  return path;
}

Result<CameraPath> torcsDefaultPath(const std::string& accPath, const DrivePathOptions& options,
                                    std::vector<std::string>* notes) {
  auto track = loadTorcsTrack(accPath);
  if (!track) return track.error();
  const std::string xml = torcsDescriptionPathFor(accPath);
  std::error_code ec;
  if (xml.empty() || !fs::is_regular_file(xml, ec)) {
    if (notes)
      notes->push_back(accPath + ": no track description " +
                       (xml.empty() ? std::string("(not a tracks/C/NAME/NAME.acc file)") : xml) +
                       "; the default path follows a trace of the road textures instead");
    DrivePathOptions o = options;
    if (o.metresPerFrame > 0) o.lengthMetres = o.metresPerFrame * std::max(1, o.frames - 1);
    return drivePath(*track, o);
  }
  auto desc = loadTorcsTrackXml(xml);
  if (!desc) return desc.error();
  auto line = integrateTorcsCentreline(*desc);
  if (!line) return line.error();
  auto reg = registerTorcsCentreline(*line, track->scene);
  if (!reg) return makeError(xml + ": " + reg.error().message);
  return torcsDrivePath(*track, *line, *reg, options);
}

}  // namespace hw::scenes
