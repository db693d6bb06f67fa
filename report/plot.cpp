// Chart rendering for benchmark reports (bench/plot.h). Lines and markers are
// antialiased by coverage: a pixel's coverage is 1 - (distance of its centre
// from the stroke edge), clamped to [0, 1], and a series' coverage is the max
// over its segments and markers, so joints are not blended twice.
#include "report/plot.h"

#include <stb_easy_font.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/check.h"
#include "core/file_io.h"

namespace hw::report {
namespace {

constexpr Rgba8 kWhite{255, 255, 255, 255};
constexpr Rgba8 kTextColour{34, 34, 34, 255};
constexpr Rgba8 kFrameColour{64, 64, 64, 255};
constexpr Rgba8 kGridColour{226, 226, 226, 255};
constexpr Rgba8 kMinorGridColour{243, 243, 243, 255};
constexpr Rgba8 kLegendBorder{190, 190, 190, 255};

constexpr int kTextScale = 2;  // stb_easy_font pixels → image pixels
constexpr int kCapHeight = 7;  // stb_easy_font glyph units, top of caps to baseline
constexpr int kDescent = 2;    // below the baseline (g, y, comma)
constexpr int kPad = 12;       // image edge to outermost text
constexpr int kTickLength = 5;
constexpr int kMinorTickLength = 3;
constexpr int kTickGap = 6;           // tick end to its label
constexpr double kLineRadius = 1.15;  // half the stroke width, pixels
constexpr double kMarkerRadius = 3.6;
constexpr double kAutoPad = 0.05;  // of the data span, each side
constexpr double kUClamp = 1e300;  // keeps spans and differences finite

// ---------------------------------------------------------------- drawing

void blend(Image<Rgba8>& im, int x, int y, Rgba8 c, double a) {
  if (x < 0 || y < 0 || x >= im.width() || y >= im.height() || a <= 0) return;
  Rgba8& d = im(x, y);
  if (a >= 1) {
    d = Rgba8{c.r, c.g, c.b, 255};
    return;
  }
  auto mix = [a](std::uint8_t dst, std::uint8_t src) {
    return static_cast<std::uint8_t>(std::lround(dst + (src - dst) * a));
  };
  d = Rgba8{mix(d.r, c.r), mix(d.g, c.g), mix(d.b, c.b), 255};
}

// Fills [x0, x1) × [y0, y1), clipped to the image.
void fillRect(Image<Rgba8>& im, int x0, int y0, int x1, int y1, Rgba8 c, double a = 1) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, im.width());
  y1 = std::min(y1, im.height());
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) blend(im, x, y, c, a);
  }
}

// Per-pixel coverage over a rectangle of the image; strokes and markers add to
// it by max, then it is composited once in one colour.
class Coverage {
 public:
  Coverage(int x0, int y0, int x1, int y1)
      : x0_(x0),
        y0_(y0),
        w_(std::max(0, x1 - x0)),
        h_(std::max(0, y1 - y0)),
        c_(static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_), 0.0f) {}

  void add(int x, int y, double c) {
    x -= x0_;
    y -= y0_;
    if (x < 0 || y < 0 || x >= w_ || y >= h_ || c <= 0) return;
    float& d = c_[static_cast<std::size_t>(y) * w_ + x];
    d = std::max(d, static_cast<float>(std::min(c, 1.0)));
  }
  float at(int x, int y) const {
    x -= x0_;
    y -= y0_;
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return 0;
    return c_[static_cast<std::size_t>(y) * w_ + x];
  }
  void composite(Image<Rgba8>& im, Rgba8 colour) const {
    for (int y = 0; y < h_; ++y) {
      for (int x = 0; x < w_; ++x)
        blend(im, x + x0_, y + y0_, colour, c_[static_cast<std::size_t>(y) * w_ + x]);
    }
  }
  int x0() const { return x0_; }
  int y0() const { return y0_; }
  int x1() const { return x0_ + w_; }
  int y1() const { return y0_ + h_; }

 private:
  int x0_, y0_, w_, h_;
  std::vector<float> c_;
};

double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }

// A stroke of half-width r along (ax, ay)-(bx, by), continuous pixel coordinates
// (pixel (i, j) has its centre at (i + 0.5, j + 0.5)). The caller clips the
// segment to near the coverage rectangle first, so its length is bounded.
void strokeSegment(Coverage& cov, double ax, double ay, double bx, double by, double r) {
  const double dx = bx - ax, dy = by - ay;
  const double len2 = dx * dx + dy * dy;
  const double len = std::sqrt(len2);
  const int steps = std::max(1, static_cast<int>(std::ceil(len)));
  const int reach = static_cast<int>(std::ceil(r + 1.5));
  for (int i = 0; i <= steps; ++i) {
    const double s = static_cast<double>(i) / steps;
    const int sx = static_cast<int>(std::floor(ax + s * dx));
    const int sy = static_cast<int>(std::floor(ay + s * dy));
    for (int py = std::max(sy - reach, cov.y0()); py <= std::min(sy + reach, cov.y1() - 1); ++py) {
      for (int px = std::max(sx - reach, cov.x0()); px <= std::min(sx + reach, cov.x1() - 1);
           ++px) {
        const double cx = px + 0.5 - ax, cy = py + 0.5 - ay;
        const double t = len2 > 0 ? clamp01((cx * dx + cy * dy) / len2) : 0.0;
        const double ex = cx - t * dx, ey = cy - t * dy;
        cov.add(px, py, clamp01(r + 0.5 - std::sqrt(ex * ex + ey * ey)));
      }
    }
  }
}

void stampMarker(Coverage& cov, double x, double y, Marker shape) {
  const int reach = static_cast<int>(std::ceil(kMarkerRadius * 1.2 + 1));
  const int cx = static_cast<int>(std::floor(x)), cy = static_cast<int>(std::floor(y));
  for (int py = cy - reach; py <= cy + reach; ++py) {
    for (int px = cx - reach; px <= cx + reach; ++px) {
      const double dx = px + 0.5 - x, dy = py + 0.5 - y;
      double c = 0;
      switch (shape) {
        case Marker::kSquare: {
          const double h = kMarkerRadius * 0.85;
          c = std::min(clamp01(h + 0.5 - std::abs(dx)), clamp01(h + 0.5 - std::abs(dy)));
          break;
        }
        case Marker::kDiamond:
          c = clamp01(kMarkerRadius * 1.25 / std::sqrt(2.0) + 0.5 -
                      (std::abs(dx) + std::abs(dy)) / std::sqrt(2.0));
          break;
        case Marker::kAuto:
        case Marker::kCircle:
          c = clamp01(kMarkerRadius + 0.5 - std::sqrt(dx * dx + dy * dy));
          break;
      }
      cov.add(px, py, c);
    }
  }
}

// Liang–Barsky: clips (x0,y0)-(x1,y1) to the box; false if nothing is left.
bool clipSegment(double& x0, double& y0, double& x1, double& y1, double bx0, double by0, double bx1,
                 double by1) {
  double t0 = 0, t1 = 1;
  const double dx = x1 - x0, dy = y1 - y0;
  const std::array<double, 4> p{-dx, dx, -dy, dy};
  const std::array<double, 4> q{x0 - bx0, bx1 - x0, y0 - by0, by1 - y0};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
    } else {
      const double t = q[i] / p[i];
      if (p[i] < 0) {
        t0 = std::max(t0, t);
      } else {
        t1 = std::min(t1, t);
      }
    }
  }
  if (t0 > t1) return false;
  const double nx0 = x0 + t0 * dx, ny0 = y0 + t0 * dy;
  x1 = x0 + t1 * dx;
  y1 = y0 + t1 * dy;
  x0 = nx0;
  y0 = ny0;
  return true;
}

// ---------------------------------------------------------------- text

struct TextRect {
  int x0, y0, x1, y1;  // glyph units, y down from the cap top
};

std::string printable(const std::string& s) {
  std::string out = s;
  for (char& ch : out) {
    if (ch < 32 || ch > 126) ch = '?';
  }
  return out;
}

std::vector<TextRect> glyphRects(const std::string& text) {
  std::string s = printable(text);
  if (s.empty()) return {};
  // stb_easy_font emits ≤ ~12 quads (64 bytes each) per glyph.
  std::vector<char> buf(s.size() * 64 * 24 + 64);
  const int quads =
      stb_easy_font_print(0, 0, s.data(), nullptr, buf.data(), static_cast<int>(buf.size()));
  std::vector<TextRect> rects;
  rects.reserve(static_cast<std::size_t>(quads));
  for (int q = 0; q < quads; ++q) {
    float xs[4], ys[4];
    for (int v = 0; v < 4; ++v) {
      const char* p = buf.data() + (q * 4 + v) * 16;
      std::memcpy(&xs[v], p, sizeof(float));
      std::memcpy(&ys[v], p + 4, sizeof(float));
    }
    rects.push_back(TextRect{static_cast<int>(std::lround(*std::min_element(xs, xs + 4))),
                             static_cast<int>(std::lround(*std::min_element(ys, ys + 4))),
                             static_cast<int>(std::lround(*std::max_element(xs, xs + 4))),
                             static_cast<int>(std::lround(*std::max_element(ys, ys + 4)))});
  }
  return rects;
}

// Ink width in image pixels at the given scale.
int textWidth(const std::string& text, int scale = kTextScale) {
  int w = 0;
  for (const TextRect& r : glyphRects(text)) w = std::max(w, r.x1);
  return w * scale;
}

int capHeight(int scale = kTextScale) { return kCapHeight * scale; }
int lineHeight(int scale = kTextScale) { return (kCapHeight + kDescent) * scale; }

// Horizontal text with its cap top-left at (x, y).
void drawText(Image<Rgba8>& im, const std::string& text, int x, int y, Rgba8 c,
              int scale = kTextScale) {
  for (const TextRect& r : glyphRects(text)) {
    fillRect(im, x + r.x0 * scale, y + r.y0 * scale, x + r.x1 * scale, y + r.y1 * scale, c);
  }
}

// Text rotated 90° anticlockwise (reads bottom to top); the glyphs' cap tops
// face left at column x and the text starts at row y going up.
void drawTextUp(Image<Rgba8>& im, const std::string& text, int x, int y, Rgba8 c,
                int scale = kTextScale) {
  for (const TextRect& r : glyphRects(text)) {
    fillRect(im, x + r.y0 * scale, y - r.x1 * scale, x + r.y1 * scale, y - r.x0 * scale, c);
  }
}

// ---------------------------------------------------------------- numbers

std::string format(const char* fmt, double v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, precision, v);
  return buf;
}

// "1.5e-05" → "1.5e-5", "1e+15" → "1e15".
std::string tidyExponent(std::string s) {
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string mant = s.substr(0, e), exp = s.substr(e + 1);
  const bool neg = !exp.empty() && exp[0] == '-';
  if (!exp.empty() && (exp[0] == '-' || exp[0] == '+')) exp.erase(0, 1);
  while (exp.size() > 1 && exp[0] == '0') exp.erase(0, 1);
  return mant + "e" + (neg ? "-" : "") + exp;
}

struct Suffix {
  double scale;
  const char* text;
};

Suffix suffixFor(double magnitude) {
  if (magnitude >= 1e12) return {1e12, "T"};
  if (magnitude >= 1e9) return {1e9, "G"};
  if (magnitude >= 1e6) return {1e6, "M"};
  if (magnitude >= 1e3) return {1e3, "k"};
  return {1, ""};
}

// A label on a linear axis whose ticks are `step` apart and reach `maxAbs`.
std::string formatLinear(double v, double step, double maxAbs) {
  if (maxAbs >= 1e15 || maxAbs < 1e-4) {
    if (v == 0) return "0";
    const int digits = std::clamp(
        static_cast<int>(std::floor(std::log10(maxAbs)) - std::floor(std::log10(step) + 1e-9)), 0,
        6);
    return tidyExponent(format("%.*e", v, digits));
  }
  const Suffix s = maxAbs >= 1e4 ? suffixFor(maxAbs) : Suffix{1, ""};
  if (v == 0 && s.scale != 1) return "0";
  const int decimals =
      std::clamp(static_cast<int>(std::ceil(-std::log10(step / s.scale) - 1e-9)), 0, 9);
  return format("%.*f", v / s.scale, decimals) + s.text;
}

// A label for m×10^k on a log axis: 0.01, 1, 500, 1k, 20M, 1e-5, 1e15.
std::string formatLog(double v) {
  if (v >= 1e15 || v < 1e-4) return tidyExponent(format("%.*g", v, 3));
  const Suffix s = suffixFor(v);
  return format("%.*g", v / s.scale, 6) + s.text;
}

// ---------------------------------------------------------------- axes

struct Axis {
  bool log = false;
  double a = 0, b = 1;        // axis range in u = log10(v) or v
  std::vector<double> ticks;  // labelled, data units
  std::vector<std::string> labels;
  std::vector<double> minor;  // unlabelled, data units

  double u(double v) const { return std::clamp(log ? std::log10(v) : v, -kUClamp, kUClamp); }
  double t(double v) const { return (u(v) - a) / (b - a); }
  double lo() const { return log ? std::pow(10.0, a) : a; }
  double hi() const { return log ? std::pow(10.0, b) : b; }
};

bool usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

bool drawable(double x, double y, const PlotOptions& o) {
  return usable(x, o.logX) && usable(y, o.logY);
}

// The axis range in u-space from the drawable data and the explicit bounds.
void setRange(Axis& axis, bool any, double dataLo, double dataHi, std::optional<double> optLo,
              std::optional<double> optHi) {
  const bool fixLo = optLo && usable(*optLo, axis.log);
  const bool fixHi = optHi && usable(*optHi, axis.log);
  double lo = 0, hi = 0;
  if (any) {
    lo = axis.u(dataLo);
    hi = axis.u(dataHi);
    const double span = hi - lo;
    lo -= kAutoPad * span;
    hi += kAutoPad * span;
  } else {
    lo = 0;
    hi = axis.log ? 2 : 1;
  }
  if (fixLo) lo = axis.u(*optLo);
  if (fixHi) hi = axis.u(*optHi);
  if (fixLo && fixHi && lo > hi) std::swap(lo, hi);
  const double mag = std::max(std::abs(lo), std::abs(hi));
  if (!(hi - lo > 1e-9 * mag) || !(hi - lo > 1e-250)) {
    // Zero (or inverted) range: pad around what was pinned, else the centre.
    const double pin = fixLo ? lo : fixHi ? hi : 0.5 * (lo + hi);
    const double pad = axis.log ? 0.5 : pin == 0 ? 1.0 : 0.1 * std::abs(pin);
    if (fixLo && !fixHi) {
      hi = lo + 2 * pad;
    } else if (fixHi && !fixLo) {
      lo = hi - 2 * pad;
    } else {
      lo = pin - pad;
      hi = pin + pad;
    }
  }
  const double lim = axis.log ? 300.0 : kUClamp;
  axis.a = std::clamp(lo, -lim, lim);
  axis.b = std::clamp(hi, -lim, lim);
  if (!(axis.b > axis.a)) axis.a = axis.b - (axis.log ? 1.0 : std::abs(axis.b) * 0.1 + 1.0);
}

// 1/2/5×10^k ticks in [lo, hi], about `target` of them.
std::vector<double> niceTicks(double lo, double hi, int target, double& stepOut) {
  const double span = hi - lo;
  const double e = std::floor(std::log10(span / std::max(target, 1)));
  double best = 0;
  double bestScore = 1e300;
  for (int k = -1; k <= 1; ++k) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double step = m * std::pow(10.0, e + k);
      const double count = std::floor(hi / step + 1e-9) - std::ceil(lo / step - 1e-9) + 1;
      const double score = std::abs(count - target) + (count < 2 ? 100 : count < 3 ? 2 : 0);
      if (score < bestScore) {
        bestScore = score;
        best = step;
      }
    }
  }
  stepOut = best;
  std::vector<double> ticks;
  const double first = std::ceil(lo / best - 1e-9), last = std::floor(hi / best + 1e-9);
  for (double i = first; i <= last && ticks.size() < 64; i += 1) {
    double v = i * best;
    if (std::abs(v) < best * 1e-9) v = 0;
    ticks.push_back(v);
  }
  return ticks;
}

void linearTicks(Axis& axis, double lo, double hi, int target) {
  double step = 1;
  axis.ticks = niceTicks(lo, hi, target, step);
  double maxAbs = 0;
  for (double v : axis.ticks) maxAbs = std::max(maxAbs, std::abs(v));
  axis.labels.clear();
  for (double v : axis.ticks) axis.labels.push_back(formatLinear(v, step, maxAbs));
}

// Ticks at density `level` (0 = densest allowed; larger = sparser), for an
// axis `lengthPx` long.
void makeTicks(Axis& axis, int level, int lengthPx, bool horizontal) {
  axis.ticks.clear();
  axis.labels.clear();
  axis.minor.clear();
  // Labels are wider than tall: ~100 px apart along x, ~60 px along y.
  const int target = std::clamp(lengthPx / (horizontal ? 100 : 60), 4, 8) - level;
  if (!axis.log) {
    linearTicks(axis, axis.a, axis.b, std::max(target, 2));
    return;
  }
  const double eps = 1e-9;
  const int k0 = static_cast<int>(std::ceil(axis.a - eps));
  const int k1 = static_cast<int>(std::floor(axis.b + eps));
  const int decades = k1 - k0 + 1;
  const double decadePx = lengthPx / (axis.b - axis.a);
  auto inRange = [&](double v) {
    const double uv = std::log10(v);
    return uv >= axis.a - eps && uv <= axis.b + eps;
  };
  if (decades >= 3) {
    const int stride = std::max(1, (decades + 7) / 8) + level;
    for (int k = k0; k <= k1; ++k) {
      const double v = std::pow(10.0, k);
      if (k % stride == 0) {
        axis.ticks.push_back(v);
        axis.labels.push_back(formatLog(v));
      } else {
        axis.minor.push_back(v);
      }
    }
    if (stride == 1 && decadePx >= 40) {
      for (int k = k0 - 1; k <= k1; ++k) {
        for (int m = 2; m <= 9; ++m) {
          const double v = m * std::pow(10.0, k);
          if (inRange(v)) axis.minor.push_back(v);
        }
      }
    }
    if (axis.ticks.size() >= 2) return;
    axis.ticks.clear();
    axis.labels.clear();
    axis.minor.clear();
  }
  // Less than ~3 decades: 1-2-5 ticks; then plain decades; then linear ticks.
  if (level <= 1) {
    const std::vector<int> majors = level == 0 ? std::vector<int>{1, 2, 5} : std::vector<int>{1};
    for (int k = k0 - 1; k <= k1; ++k) {
      for (int m = 1; m <= 9; ++m) {
        const double v = m * std::pow(10.0, k);
        if (!inRange(v)) continue;
        if (std::find(majors.begin(), majors.end(), m) != majors.end()) {
          axis.ticks.push_back(v);
          axis.labels.push_back(formatLog(v));
        } else {
          axis.minor.push_back(v);
        }
      }
    }
    if (axis.ticks.size() >= 3 || (level == 1 && axis.ticks.size() >= 2)) return;
    axis.ticks.clear();
    axis.labels.clear();
    axis.minor.clear();
  }
  linearTicks(axis, axis.lo(), axis.hi(), std::max(target, 3));
  // Rounding can put a linear tick at or below 0 when lo() is tiny.
  for (std::size_t i = axis.ticks.size(); i-- > 0;) {
    if (!(axis.ticks[i] > 0)) {
      axis.ticks.erase(axis.ticks.begin() + static_cast<std::ptrdiff_t>(i));
      axis.labels.erase(axis.labels.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
}

// ---------------------------------------------------------------- layout

struct Layout {
  PlotRect rect;
  Axis x, y;
  int titleScale = kTextScale;
  int legendRight = 0;  // pixels kept right of the plot area for a legend beside it
  int legendBelow = 0;  // pixels kept at the bottom for a legend below the axis labels
};

// Pixel position of the centre of data coordinate t ∈ [0, 1].
double pixelX(const PlotRect& r, double t) { return r.x0 + 0.5 + t * (r.x1 - r.x0 - 1); }
double pixelY(const PlotRect& r, double t) { return r.y1 - 0.5 - t * (r.y1 - r.y0 - 1); }

int maxWidth(const std::vector<std::string>& labels) {
  int w = 0;
  for (const std::string& s : labels) w = std::max(w, textWidth(s));
  return w;
}

// Do the labels of `axis` fit along it without touching?
bool labelsFit(const Axis& axis, bool horizontal, int lengthPx) {
  if (axis.ticks.size() < 2) return true;
  for (std::size_t i = 1; i < axis.ticks.size(); ++i) {
    const double gapPx = (axis.t(axis.ticks[i]) - axis.t(axis.ticks[i - 1])) * lengthPx;
    const double need = horizontal
                            ? 0.5 * (textWidth(axis.labels[i]) + textWidth(axis.labels[i - 1])) + 14
                            : lineHeight() + 6;
    if (gapPx < need) return false;
  }
  return true;
}

void fitTicks(Axis& axis, bool horizontal, int lengthPx) {
  for (int level = 0; level < 12; ++level) {
    makeTicks(axis, level, lengthPx, horizontal);
    if (labelsFit(axis, horizontal, lengthPx)) return;
  }
}

PlotRect rectFromMargins(const Layout& l, const PlotOptions& o) {
  const int th = capHeight(), lh = lineHeight();
  int top = o.title.empty() ? kPad + th / 2 : kPad + capHeight(l.titleScale) + 14;
  int left = kPad + maxWidth(l.y.labels) + kTickGap + kTickLength;
  if (!o.yLabel.empty()) left += lh + 10;
  int bottom = kTickLength + kTickGap + lh + kPad;
  if (!o.xLabel.empty()) bottom += lh + 6;
  int right = kPad + 8;
  if (!l.x.labels.empty()) right = std::max(right, textWidth(l.x.labels.back()) / 2 + kPad);
  right += l.legendRight;
  bottom += l.legendBelow;
  PlotRect r;
  r.x0 = std::clamp(left, 0, std::max(0, o.width - 2));
  r.x1 = std::clamp(o.width - right, r.x0 + 1, o.width);
  r.y0 = std::clamp(top, 0, std::max(0, o.height - 2));
  r.y1 = std::clamp(o.height - bottom, r.y0 + 1, o.height);
  return r;
}

Layout computeLayout(const std::vector<Series>& series, const PlotOptions& o,
                     int legendRight = 0, int legendBelow = 0) {
  HW_CHECK_GE(o.width, 1);
  HW_CHECK_GE(o.height, 1);
  Layout l;
  l.legendRight = legendRight;
  l.legendBelow = legendBelow;
  l.x.log = o.logX;
  l.y.log = o.logY;
  bool any = false;
  double xLo = 0, xHi = 0, yLo = 0, yHi = 0;
  for (const Series& s : series) {
    HW_CHECK_EQ(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!drawable(s.x[i], s.y[i], o)) continue;
      if (!any) {
        xLo = xHi = s.x[i];
        yLo = yHi = s.y[i];
        any = true;
      }
      xLo = std::min(xLo, s.x[i]);
      xHi = std::max(xHi, s.x[i]);
      yLo = std::min(yLo, s.y[i]);
      yHi = std::max(yHi, s.y[i]);
    }
  }
  setRange(l.x, any, xLo, xHi, o.xMin, o.xMax);
  setRange(l.y, any, yLo, yHi, o.yMin, o.yMax);
  if (!o.title.empty() && textWidth(o.title, 3) + 2 * kPad <= o.width) l.titleScale = 3;

  // Ticks depend on the plot size, which depends on the tick labels: iterate
  // from a guess; the last rectangle is computed from the final labels.
  l.rect = PlotRect{90, 40, std::max(91, o.width - 30), std::max(41, o.height - 70)};
  for (int pass = 0; pass < 3; ++pass) {
    fitTicks(l.x, true, l.rect.x1 - l.rect.x0);
    fitTicks(l.y, false, l.rect.y1 - l.rect.y0);
    l.rect = rectFromMargins(l, o);
  }
  return l;
}

// ---------------------------------------------------------------- pieces

void drawAxes(Image<Rgba8>& im, const Layout& l, const PlotOptions& o) {
  const PlotRect& r = l.rect;
  const int th = capHeight(), lh = lineHeight();
  auto col = [&](double v) {
    return static_cast<int>(std::clamp(std::floor(pixelX(r, l.x.t(v))), double(r.x0), r.x1 - 1.0));
  };
  auto row = [&](double v) {
    return static_cast<int>(std::clamp(std::floor(pixelY(r, l.y.t(v))), double(r.y0), r.y1 - 1.0));
  };
  // Grid first (under the data), then frame, ticks and labels.
  for (double v : l.x.minor) fillRect(im, col(v), r.y0, col(v) + 1, r.y1, kMinorGridColour);
  for (double v : l.y.minor) fillRect(im, r.x0, row(v), r.x1, row(v) + 1, kMinorGridColour);
  for (double v : l.x.ticks) fillRect(im, col(v), r.y0, col(v) + 1, r.y1, kGridColour);
  for (double v : l.y.ticks) fillRect(im, r.x0, row(v), r.x1, row(v) + 1, kGridColour);

  fillRect(im, r.x0 - 1, r.y0 - 1, r.x1 + 1, r.y0, kFrameColour);
  fillRect(im, r.x0 - 1, r.y1, r.x1 + 1, r.y1 + 1, kFrameColour);
  fillRect(im, r.x0 - 1, r.y0 - 1, r.x0, r.y1 + 1, kFrameColour);
  fillRect(im, r.x1, r.y0 - 1, r.x1 + 1, r.y1 + 1, kFrameColour);

  for (double v : l.x.minor)
    fillRect(im, col(v), r.y1 + 1, col(v) + 1, r.y1 + 1 + kMinorTickLength, kFrameColour);
  for (double v : l.y.minor)
    fillRect(im, r.x0 - 1 - kMinorTickLength, row(v), r.x0 - 1, row(v) + 1, kFrameColour);
  for (std::size_t i = 0; i < l.x.ticks.size(); ++i) {
    const int c = col(l.x.ticks[i]);
    fillRect(im, c, r.y1 + 1, c + 1, r.y1 + 1 + kTickLength, kFrameColour);
    const int w = textWidth(l.x.labels[i]);
    const int x = std::clamp(c - w / 2, 0, std::max(0, o.width - w));
    drawText(im, l.x.labels[i], x, r.y1 + 1 + kTickLength + kTickGap, kTextColour);
  }
  for (std::size_t i = 0; i < l.y.ticks.size(); ++i) {
    const int rr = row(l.y.ticks[i]);
    fillRect(im, r.x0 - 1 - kTickLength, rr, r.x0 - 1, rr + 1, kFrameColour);
    const int w = textWidth(l.y.labels[i]);
    const int y = std::clamp(rr - th / 2, 0, std::max(0, o.height - th));
    drawText(im, l.y.labels[i], r.x0 - 1 - kTickLength - kTickGap - w, y, kTextColour);
  }

  if (!o.title.empty()) {
    const int w = textWidth(o.title, l.titleScale);
    const int x = std::clamp((r.x0 + r.x1 - w) / 2, 0, std::max(0, o.width - w));
    drawText(im, o.title, x, kPad, kTextColour, l.titleScale);
  }
  if (!o.xLabel.empty()) {
    const int w = textWidth(o.xLabel);
    const int x = std::clamp((r.x0 + r.x1 - w) / 2, 0, std::max(0, o.width - w));
    drawText(im, o.xLabel, x, r.y1 + 1 + kTickLength + kTickGap + lh + 6, kTextColour);
  }
  if (!o.yLabel.empty()) {
    const int w = textWidth(o.yLabel);
    const int y = std::clamp((r.y0 + r.y1 + w) / 2, std::min(w, o.height - 1), o.height - 1);
    drawTextUp(im, o.yLabel, kPad, y, kTextColour);
  }
}

struct Style {
  Rgba8 colour;
  Marker marker;
};

std::vector<Style> styles(const std::vector<Series>& series) {
  std::vector<Style> out;
  std::size_t autoIndex = 0;
  for (std::size_t i = 0; i < series.size(); ++i) {
    Style st;
    st.colour = series[i].colour == Rgba8{} ? plotPalette()[autoIndex++ % plotPalette().size()]
                                            : series[i].colour;
    st.colour.a = 255;
    st.marker = series[i].marker;
    if (st.marker == Marker::kAuto) {
      static constexpr std::array<Marker, 3> kCycle{Marker::kCircle, Marker::kSquare,
                                                    Marker::kDiamond};
      st.marker = kCycle[i % kCycle.size()];
    }
    out.push_back(st);
  }
  return out;
}

// Draws one series; returns its coverage (for legend placement).
Coverage drawSeries(Image<Rgba8>& im, const Layout& l, const Series& s, const Style& st,
                    const PlotOptions& o) {
  const PlotRect& r = l.rect;
  Coverage cov(r.x0, r.y0, r.x1, r.y1);
  // Clip in u-space to the axis range grown by a few pixels, so huge
  // coordinates never reach pixel arithmetic.
  const double mx = 4.0 * (l.x.b - l.x.a) / std::max(1, r.x1 - r.x0);
  const double my = 4.0 * (l.y.b - l.y.a) / std::max(1, r.y1 - r.y0);
  auto toPx = [&](double ux, double uy, double& px, double& py) {
    px = pixelX(r, (ux - l.x.a) / (l.x.b - l.x.a));
    py = pixelY(r, (uy - l.y.a) / (l.y.b - l.y.a));
  };
  if (s.lines) {
    for (std::size_t i = 1; i < s.x.size(); ++i) {
      if (!drawable(s.x[i - 1], s.y[i - 1], o) || !drawable(s.x[i], s.y[i], o)) continue;
      double ux0 = l.x.u(s.x[i - 1]), uy0 = l.y.u(s.y[i - 1]);
      double ux1 = l.x.u(s.x[i]), uy1 = l.y.u(s.y[i]);
      if (!clipSegment(ux0, uy0, ux1, uy1, l.x.a - mx, l.y.a - my, l.x.b + mx, l.y.b + my))
        continue;
      double ax, ay, bx, by;
      toPx(ux0, uy0, ax, ay);
      toPx(ux1, uy1, bx, by);
      strokeSegment(cov, ax, ay, bx, by, kLineRadius);
    }
  }
  if (s.markers) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!drawable(s.x[i], s.y[i], o)) continue;
      const double ux = l.x.u(s.x[i]), uy = l.y.u(s.y[i]);
      if (ux < l.x.a - mx || ux > l.x.b + mx || uy < l.y.a - my || uy > l.y.b + my) continue;
      double px, py;
      toPx(ux, uy, px, py);
      stampMarker(cov, px, py, st.marker);
    }
  }
  cov.composite(im, st.colour);
  return cov;
}

// The legend box: its entries (labelled series) and size in pixels.
struct LegendBox {
  std::vector<std::size_t> entries;
  int textW = 0, rowH = 0, w = 0, h = 0;
};
constexpr int kLegendInset = 10;  // from the plot frame, pixels

LegendBox legendBox(const std::vector<Series>& series) {
  LegendBox b;
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (series[i].label.empty()) continue;
    b.entries.push_back(i);
    b.textW = std::max(b.textW, textWidth(series[i].label));
  }
  b.rowH = capHeight() + 10;
  b.w = 10 + 32 + 8 + b.textW + 12;
  b.h = static_cast<int>(b.entries.size()) * b.rowH + 8;
  return b;
}

// The plot-area corner that hides the least data (ties: top-right, top-left,
// bottom-right, bottom-left) and how many data pixels it hides.
std::array<int, 2> freestCorner(const Layout& l, const LegendBox& b,
                                const std::vector<unsigned char>& occupied, long* hiddenOut) {
  const PlotRect& r = l.rect;
  const int inset = kLegendInset;
  const std::array<std::array<int, 2>, 4> corners{{{r.x1 - inset - b.w, r.y0 + inset},
                                                   {r.x0 + inset, r.y0 + inset},
                                                   {r.x1 - inset - b.w, r.y1 - inset - b.h},
                                                   {r.x0 + inset, r.y1 - inset - b.h}}};
  const int w = r.x1 - r.x0;
  long best = -1;
  std::array<int, 2> at = corners[0];
  for (const auto& c : corners) {
    long hidden = 0;
    for (int y = std::max(c[1], r.y0); y < std::min(c[1] + b.h, r.y1); ++y) {
      for (int x = std::max(c[0], r.x0); x < std::min(c[0] + b.w, r.x1); ++x) {
        hidden += occupied[static_cast<std::size_t>(y - r.y0) * w + (x - r.x0)];
      }
    }
    if (best < 0 || hidden < best) {
      best = hidden;
      at = c;
    }
  }
  *hiddenOut = best;
  return at;
}

// Draws the legend box with its top-left at (bx, by); swatches are clipped
// to `clip` (the plot area for a legend inside it, the image beside it).
void drawLegend(Image<Rgba8>& im, const LegendBox& b, int bx, int by, const PlotRect& clip,
                const std::vector<Series>& series, const std::vector<Style>& st) {
  const int th = capHeight();
  const int rowH = b.rowH, swatchW = 32, boxW = b.w, boxH = b.h;
  fillRect(im, bx, by, bx + boxW, by + boxH, kWhite, 0.88);
  fillRect(im, bx, by, bx + boxW, by + 1, kLegendBorder);
  fillRect(im, bx, by + boxH - 1, bx + boxW, by + boxH, kLegendBorder);
  fillRect(im, bx, by, bx + 1, by + boxH, kLegendBorder);
  fillRect(im, bx + boxW - 1, by, bx + boxW, by + boxH, kLegendBorder);
  for (std::size_t e = 0; e < b.entries.size(); ++e) {
    const Series& s = series[b.entries[e]];
    const int rowTop = by + 4 + static_cast<int>(e) * rowH;
    const double cy = rowTop + rowH / 2.0;
    Coverage cov(std::max(bx, clip.x0), std::max(rowTop, clip.y0), std::min(bx + boxW, clip.x1),
                 std::min(rowTop + rowH, clip.y1));
    const double sx0 = bx + 10, sx1 = bx + 10 + swatchW;
    if (s.lines || !s.markers) strokeSegment(cov, sx0, cy, sx1, cy, kLineRadius);
    if (s.markers) stampMarker(cov, 0.5 * (sx0 + sx1), cy, st[b.entries[e]].marker);
    cov.composite(im, st[b.entries[e]].colour);
    drawText(im, s.label, bx + 10 + swatchW + 8, rowTop + (rowH - th) / 2, kTextColour);
  }
}

// Axes and series of layout l into im; the plot-area pixels any series covers.
std::vector<unsigned char> drawData(Image<Rgba8>& im, const Layout& l,
                                    const std::vector<Series>& series,
                                    const std::vector<Style>& st, const PlotOptions& o) {
  drawAxes(im, l, o);
  const PlotRect& r = l.rect;
  std::vector<unsigned char> occupied(
      static_cast<std::size_t>(r.x1 - r.x0) * static_cast<std::size_t>(r.y1 - r.y0), 0);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Coverage cov = drawSeries(im, l, series[i], st[i], o);
    for (int y = r.y0; y < r.y1; ++y) {
      for (int x = r.x0; x < r.x1; ++x) {
        if (cov.at(x, y) > 0)
          occupied[static_cast<std::size_t>(y - r.y0) * (r.x1 - r.x0) + (x - r.x0)] = 1;
      }
    }
  }
  // Point labels: above right of the marker, else above left, below right,
  // below left; inside the plot area and clear of every label placed before
  // (1 px apart), or not at all. They count as data for the legend.
  std::vector<PlotRect> placed;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    if (s.pointLabels.size() != s.x.size()) continue;
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const std::string& text = s.pointLabels[k];
      if (text.empty() || !drawable(s.x[k], s.y[k], o)) continue;
      const double tx = l.x.t(s.x[k]), ty = l.y.t(s.y[k]);
      if (!(tx >= 0 && tx <= 1 && ty >= 0 && ty <= 1)) continue;
      const int px = static_cast<int>(pixelX(r, tx)), py = static_cast<int>(pixelY(r, ty));
      const int tw = textWidth(text, 1), th = capHeight(1), gap = 6;
      const int xs[2] = {px + gap, px - gap - tw}, ys[2] = {py - gap - th, py + gap};
      bool found = false;
      int x = 0, y = 0;
      for (int c = 0; c < 4 && !found; ++c) {
        x = xs[c % 2];
        y = ys[c / 2];
        if (x < r.x0 || x + tw > r.x1 || y < r.y0 || y + th > r.y1) continue;
        found = true;
        for (const PlotRect& p : placed)
          if (x < p.x1 + 1 && p.x0 < x + tw + 1 && y < p.y1 + 1 && p.y0 < y + th + 1) found = false;
      }
      if (!found) continue;
      placed.push_back({x, y, x + tw, y + th});
      drawText(im, text, x, y, st[i].colour, 1);
      for (int yy = y; yy < y + th; ++yy)
        for (int xx = x; xx < x + tw; ++xx)
          occupied[static_cast<std::size_t>(yy - r.y0) * (r.x1 - r.x0) + (xx - r.x0)] = 1;
    }
  }
  return occupied;
}

// The chart and where its legend goes: in the plot-area corner that hides no
// data; when every corner would hide some, beside the plot area (which then
// narrows) if it keeps half its width, else below the x axis (the plot area
// then gets lower) if it keeps half its height; else the corner hiding least.
struct Rendered {
  Image<Rgba8> image;
  Layout layout;
};
Rendered render(const std::vector<Series>& series, const PlotOptions& o) {
  const std::vector<Style> st = styles(series);
  const LegendBox box = legendBox(series);
  Rendered out{Image<Rgba8>(o.width, o.height, kWhite), computeLayout(series, o)};
  std::vector<unsigned char> occupied = drawData(out.image, out.layout, series, st, o);
  if (box.entries.empty()) return out;
  long hidden = 0;
  std::array<int, 2> at = freestCorner(out.layout, box, occupied, &hidden);
  const int beside = box.w + kLegendInset;
  const PlotRect& r0 = out.layout.rect;
  if (hidden > 0 && (r0.x1 - r0.x0) - beside >= (r0.x1 - r0.x0) / 2 &&
      r0.y0 + box.h <= o.height) {
    out.layout = computeLayout(series, o, beside);
    out.image = Image<Rgba8>(o.width, o.height, kWhite);
    drawData(out.image, out.layout, series, st, o);
    const PlotRect& r = out.layout.rect;
    drawLegend(out.image, box, r.x1 + kLegendInset, r.y0, PlotRect{0, 0, o.width, o.height},
               series, st);
    return out;
  }
  const int below = box.h + 6;
  if (hidden > 0 && (r0.y1 - r0.y0) - below >= (r0.y1 - r0.y0) / 2 &&
      r0.x0 + box.w <= o.width) {
    out.layout = computeLayout(series, o, 0, below);
    out.image = Image<Rgba8>(o.width, o.height, kWhite);
    drawData(out.image, out.layout, series, st, o);
    drawLegend(out.image, box, out.layout.rect.x0, o.height - box.h - 4,
               PlotRect{0, 0, o.width, o.height}, series, st);
    return out;
  }
  drawLegend(out.image, box, at[0], at[1], out.layout.rect, series, st);
  return out;
}

}  // namespace

const std::vector<Rgba8>& plotPalette() {
  static const std::vector<Rgba8> kTab10{
      {31, 119, 180, 255},  {255, 127, 14, 255}, {44, 160, 44, 255},   {214, 39, 40, 255},
      {148, 103, 189, 255}, {140, 86, 75, 255},  {227, 119, 194, 255}, {127, 127, 127, 255},
      {188, 189, 34, 255},  {23, 190, 207, 255}};
  return kTab10;
}

PlotRect plotArea(const std::vector<Series>& series, const PlotOptions& options) {
  return render(series, options).layout.rect;
}

Image<Rgba8> renderPlot(const std::vector<Series>& series, const PlotOptions& options) {
  return render(series, options).image;
}

Status writePlot(const std::string& pngPath, const std::vector<Series>& series,
                 const PlotOptions& options) {
  return writePng(pngPath, renderPlot(series, options));
}

void drawCaption(Image<Rgba8>& image, const std::string& text, int x, int y, Rgba8 colour) {
  drawText(image, text, x, y, colour);
}

int captionHeight() { return lineHeight(); }

}  // namespace hw::report
