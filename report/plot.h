#pragma once
// A tiny dependency-free line/scatter chart renderer for benchmark reports:
// axes with "nice" 1/2/5×10^k (or decade) ticks, grid, title, axis labels and
// a legend, drawn with antialiased lines and stb_easy_font text into an RGBA8.
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/result.h"

namespace hw::report {

enum class Marker { kAuto, kCircle, kSquare, kDiamond };

struct Series {
  std::string label{};           // empty: not listed in the legend
  std::vector<double> x{}, y{};  // same length (checked); points are drawn in the given order
  Rgba8 colour{};     // all-zero {} = next tab10 palette colour; drawn opaque, alpha ignored
  bool lines = true;  // polyline through the points, broken at skipped points
  bool markers = true;
  Marker marker = Marker::kAuto;  // kAuto cycles circle, square, diamond by series index
  // Text beside each point (e.g. its τ), small, in the series colour; empty =
  // none, else one per point ("" = no text). Labels that do not fit inside
  // the plot area, or would overlap a label placed before them (earlier
  // series, earlier points), are left out.
  std::vector<std::string> pointLabels{};
};

// All defaults work. Unset axis bounds come from the drawable data, padded by
// 5% of its span (of log10 span on log axes). A zero range is padded by ±10%
// (±1 around 0; ±half a decade on log axes); with no drawable data an axis
// shows [0, 1] (linear) or [1, 100] (log). Explicit bounds that are non-finite,
// or non-positive on a log axis, are ignored; swapped bounds are swapped back.
struct PlotOptions {
  int width = 800, height = 500;            // pixels, >= 1 (checked)
  std::string title{}, xLabel{}, yLabel{};  // printable ASCII; other bytes draw as '?'
  bool logX = false, logY = false;
  std::optional<double> xMin{}, xMax{}, yMin{}, yMax{};
};

// Where the data lands: the inner plot area in pixels, [x0, x1) × [y0, y1),
// row 0 at the top. Series pixels (lines, markers) lie only inside it, and
// so do legend swatches unless the legend stands beside it (renderPlot).
struct PlotRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

// Renders the chart on a white background. Points with a non-finite
// coordinate, or a non-positive one on a log axis, are skipped (the line is
// broken there). Lines and markers are clipped to the plot area. Labelled
// series get a legend entry: in a plot-area corner where it hides no data,
// else beside the plot area, right of it (the plot area narrows; only when
// it keeps at least half its width), else below the x axis (the plot area
// gets lower; only when it keeps half its height), else in the corner
// hiding the least.
Image<Rgba8> renderPlot(const std::vector<Series>& series, const PlotOptions& options);

// The plot area renderPlot() uses for the same arguments.
PlotRect plotArea(const std::vector<Series>& series, const PlotOptions& options);

// renderPlot() then an atomic PNG write; errors are file errors.
Status writePlot(const std::string& pngPath, const std::vector<Series>& series,
                 const PlotOptions& options);

// Text as the plots draw it (stb_easy_font, 2x), its cap top-left at (x, y);
// clipped to the image. captionHeight() is one line's height in pixels.
void drawCaption(Image<Rgba8>& image, const std::string& text, int x, int y, Rgba8 colour);
int captionHeight();

// The palette of automatic colours (tab10, Vega/matplotlib), in order.
const std::vector<Rgba8>& plotPalette();

}  // namespace hw::report
