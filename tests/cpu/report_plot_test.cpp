// Chart rendering (bench/plot.h): the image has the requested size, each
// series shows up in its own colour inside the plot area and nowhere else,
// and awkward data (NaN/Inf, non-positive values on log axes, empty and
// zero-range input) renders without crashing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "report/plot.h"

namespace hw::report {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Count {
  long inside = 0;
  long outside = 0;
};

Count countColour(const Image<Rgba8>& im, const PlotRect& r, Rgba8 c) {
  Count n;
  for (int y = 0; y < im.height(); ++y) {
    for (int x = 0; x < im.width(); ++x) {
      if (im(x, y) != c) continue;
      (r.contains(x, y) ? n.inside : n.outside) += 1;
    }
  }
  return n;
}

long countInRect(const Image<Rgba8>& im, const PlotRect& r, Rgba8 c) {
  return countColour(im, r, c).inside;
}

Series line(std::string label, std::vector<double> x, std::vector<double> y) {
  Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  return s;
}

std::vector<double> ramp(int n, double from, double step) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(from + i * step);
  return v;
}

bool sane(const PlotRect& r, const PlotOptions& o) {
  return r.x0 >= 0 && r.y0 >= 0 && r.x1 <= o.width && r.y1 <= o.height && r.x1 > r.x0 &&
         r.y1 > r.y0;
}

TEST(Plot, ImageHasRequestedSizeAndWhiteBackground) {
  for (auto [w, h] :
       {std::pair{800, 500}, std::pair{321, 207}, std::pair{40, 30}, std::pair{1, 1}}) {
    // (Designated initialisers: GCC 12 warns falsely on string = "literal" at -O3.)
    const PlotOptions o{.width = w, .height = h, .title = "Title", .xLabel = "x", .yLabel = "y"};
    const std::vector<Series> s{line("a", {1, 2, 3}, {3, 1, 2})};
    const Image<Rgba8> im = renderPlot(s, o);
    EXPECT_EQ(im.width(), w);
    EXPECT_EQ(im.height(), h);
    EXPECT_TRUE(sane(plotArea(s, o), o)) << w << "x" << h;
  }
  PlotOptions o;
  const Image<Rgba8> im = renderPlot({}, o);
  EXPECT_EQ(im(0, 0), (Rgba8{255, 255, 255, 255}));
  EXPECT_EQ(im(o.width - 1, o.height - 1), (Rgba8{255, 255, 255, 255}));
}

TEST(Plot, SeriesColourOnlyInsidePlotArea) {
  const PlotOptions o{.title = "Throughput", .xLabel = "frames", .yLabel = "ms"};
  Series s = line("walk", ramp(20, 0, 1), ramp(20, 5, 0.5));
  s.colour = Rgba8{200, 30, 150, 255};
  const std::vector<Series> all{s};
  const Image<Rgba8> im = renderPlot(all, o);
  const Count n = countColour(im, plotArea(all, o), s.colour);
  EXPECT_GT(n.inside, 200);  // 20 markers and a long 2-px line
  EXPECT_EQ(n.outside, 0);
}

// Data through every corner of the plot area (an X and a frame): no corner
// is free, so the legend stands beside the plot area and hides nothing; its
// swatch is the only series colour outside the plot area.
TEST(Plot, LegendGoesBesideThePlotWhenEveryCornerHoldsData) {
  PlotOptions o;
  o.xMin = 0, o.xMax = 1, o.yMin = 0, o.yMax = 1;
  Series s = line("series a", {0, 1, 1, 0, 0, 1}, {0, 1, 0, 1, 0, 0});
  s.markers = false;
  s.colour = Rgba8{200, 30, 30, 255};
  const PlotRect inside = plotArea({}, o);
  const PlotRect r = plotArea({s}, o);
  EXPECT_LT(r.x1, inside.x1);  // narrowed to make room
  const Image<Rgba8> im = renderPlot({s}, o);
  const Count n = countColour(im, r, s.colour);
  EXPECT_GT(n.inside, 100);
  EXPECT_GT(n.outside, 0);  // the swatch
  for (int y = 0; y < im.height(); ++y) {
    for (int x = 0; x < r.x1 + 2; ++x) {
      if (im(x, y) == s.colour) {
        EXPECT_TRUE(r.contains(x, y)) << x << "," << y;
      }
    }
  }
}

// Data in one corner only: the legend stays inside, in a free corner.
TEST(Plot, LegendStaysInAFreeCorner) {
  PlotOptions o;
  o.xMin = 0, o.xMax = 1, o.yMin = 0, o.yMax = 1;
  Series s = line("label", {0, 0.2}, {0, 0.2});
  s.colour = Rgba8{30, 30, 200, 255};
  EXPECT_EQ(plotArea({s}, o).x1, plotArea({}, o).x1);
  EXPECT_EQ(countColour(renderPlot({s}, o), plotArea({s}, o), s.colour).outside, 0);
}

TEST(Plot, AutomaticColoursComeFromThePalette) {
  const std::vector<Series> all{line("a", {0, 1}, {0, 1}), line("b", {0, 1}, {1, 0})};
  PlotOptions o;
  const Image<Rgba8> im = renderPlot(all, o);
  const PlotRect r = plotArea(all, o);
  const Rgba8 c0 = plotPalette()[0], c1 = plotPalette()[1];
  ASSERT_NE(c0, c1);
  const Count n0 = countColour(im, r, c0), n1 = countColour(im, r, c1);
  EXPECT_GT(n0.inside, 100);
  EXPECT_GT(n1.inside, 100);
  // The X reaches every corner, so the legend stands right of the plot area:
  // its swatches are the only series pixels outside it.
  for (int y = 0; y < im.height(); ++y) {
    for (int x = 0; x <= r.x1; ++x) {
      if (im(x, y) == c0 || im(x, y) == c1) {
        EXPECT_TRUE(r.contains(x, y)) << x << "," << y;
      }
    }
  }
}

TEST(Plot, LinesAreClippedToThePlotArea) {
  PlotOptions o;
  o.xMin = 0;
  o.xMax = 1;
  o.yMin = 0;
  o.yMax = 1;
  // Far outside the explicit range, including huge coordinates.
  Series s = line("", {-5, 0.5, 1e300, 0.5}, {-5, 0.5, 3, -1e300});
  s.colour = Rgba8{10, 200, 10, 255};
  const std::vector<Series> all{s};
  const Image<Rgba8> im = renderPlot(all, o);
  const Count n = countColour(im, plotArea(all, o), s.colour);
  EXPECT_GT(n.inside, 100);
  EXPECT_EQ(n.outside, 0);
}

TEST(Plot, LogAxesSkipNonPositiveValues) {
  PlotOptions o;
  o.logX = true;
  o.logY = true;
  Series s = line("x", {0, -1, 1, 10, 100, 1000}, {5, 6, 0, -3, 100, 1e4});
  s.colour = Rgba8{0, 0, 255, 255};
  const std::vector<Series> all{s};
  const Image<Rgba8> im = renderPlot(all, o);
  const PlotRect r = plotArea(all, o);
  EXPECT_TRUE(sane(r, o));
  // Only (100, 100) and (1000, 1e4) are drawable: markers and one segment.
  const Count n = countColour(im, r, s.colour);
  EXPECT_GT(n.inside, 50);
  EXPECT_EQ(n.outside, 0);

  // Nothing drawable at all, and non-positive explicit bounds (ignored).
  o.xMin = -1;
  o.yMax = 0;
  const std::vector<Series> none{line("none", {0, -1}, {-2, 0})};
  const Image<Rgba8> empty = renderPlot(none, o);
  EXPECT_EQ(empty.width(), o.width);
  EXPECT_EQ(countColour(empty, plotArea(none, o), plotPalette()[0]).outside, 0);
}

TEST(Plot, NonFiniteValuesAreSkipped) {
  PlotOptions o;
  Series s = line("s", {0, 1, kNaN, 3, 4, kInf, 6}, {0, 1, 2, -kInf, 4, 5, kNaN});
  s.colour = Rgba8{250, 100, 0, 255};
  const std::vector<Series> all{s};
  const Image<Rgba8> im = renderPlot(all, o);
  const PlotRect r = plotArea(all, o);
  EXPECT_TRUE(sane(r, o));
  const Count n = countColour(im, r, s.colour);
  EXPECT_GT(n.inside, 50);
  EXPECT_EQ(n.outside, 0);
  // The range comes from the finite points only: (0, 0), (1, 1), (4, 4).
  // The line (0,0)-(1,1) is drawn, (1,1)-(4,4) is not (broken at the NaN).
  const Series onlyFinite = [&] {
    Series t = s;
    t.x = {0, 1};
    t.y = {0, 1};
    t.markers = false;
    return t;
  }();
  PlotOptions fixed = o;
  fixed.xMin = 0;
  fixed.xMax = 4;
  fixed.yMin = 0;
  fixed.yMax = 4;
  Series noMarkers = s;
  noMarkers.markers = false;
  const Image<Rgba8> a = renderPlot({noMarkers}, fixed);
  const Image<Rgba8> b = renderPlot({onlyFinite}, fixed);
  EXPECT_EQ(countInRect(a, plotArea({noMarkers}, fixed), s.colour),
            countInRect(b, plotArea({onlyFinite}, fixed), s.colour));
}

TEST(Plot, EmptyInputDrawsAxesOnly) {
  const PlotOptions o{.title = "nothing"};
  for (const std::vector<Series>& all :
       {std::vector<Series>{}, std::vector<Series>{line("", {}, {})}}) {
    const Image<Rgba8> im = renderPlot(all, o);
    const PlotRect r = plotArea(all, o);
    ASSERT_TRUE(sane(r, o));
    long ink = 0;  // dark pixels: frame, ticks, text
    for (const Rgba8& p : im.pixels()) ink += p.r < 128 ? 1 : 0;
    EXPECT_GT(ink, 2 * ((r.x1 - r.x0) + (r.y1 - r.y0)));
    for (const Rgba8& c : plotPalette()) {
      EXPECT_EQ(countColour(im, r, c).inside + countColour(im, r, c).outside, 0);
    }
  }
}

TEST(Plot, TwoSeriesInTwoColours) {
  const std::vector<Series> all{line("fast", ramp(10, 1, 1), ramp(10, 1, 1)),
                                line("slow", ramp(10, 1, 1), ramp(10, 30, -2))};
  PlotOptions o;
  const Image<Rgba8> im = renderPlot(all, o);
  const PlotRect r = plotArea(all, o);
  EXPECT_GT(countInRect(im, r, plotPalette()[0]), 100);
  EXPECT_GT(countInRect(im, r, plotPalette()[1]), 100);
  // An explicit colour replaces the palette entry, the next automatic series
  // still starts at the palette's first colour.
  std::vector<Series> mixed = all;
  mixed[0].colour = Rgba8{0, 0, 0, 255};
  const Image<Rgba8> im2 = renderPlot(mixed, o);
  EXPECT_GT(countInRect(im2, r, Rgba8{0, 0, 0, 255}), 100);
  EXPECT_GT(countInRect(im2, r, plotPalette()[0]), 100);
}

TEST(Plot, DegenerateRanges) {
  struct Case {
    std::vector<double> x, y;
    bool logX, logY;
  };
  const std::vector<Case> cases{
      {{3}, {7}, false, false},                          // single point
      {{0}, {0}, false, false},                          // single point at the origin
      {{1, 2, 3}, {5, 5, 5}, false, false},              // flat line
      {{2, 2, 2}, {1, 2, 3}, false, false},              // vertical line
      {{1, 10, 100}, {8, 8, 8}, true, true},             // flat line on log axes
      {{1e15, 1e15 + 1}, {1e-20, 2e-20}, false, false},  // tiny relative / absolute spans
      {{-1e300, 1e300}, {1e-300, 1e300}, false, true},   // huge spans
  };
  for (const Case& c : cases) {
    PlotOptions o;
    o.logX = c.logX;
    o.logY = c.logY;
    Series s = line("s", c.x, c.y);
    s.colour = Rgba8{123, 45, 67, 255};
    const std::vector<Series> all{s};
    const Image<Rgba8> im = renderPlot(all, o);
    const PlotRect r = plotArea(all, o);
    ASSERT_TRUE(sane(r, o));
    const Count n = countColour(im, r, s.colour);
    EXPECT_GT(n.inside, 20) << c.x.front() << "," << c.y.front();
    EXPECT_EQ(n.outside, 0);
  }
  // Explicit equal and swapped bounds.
  PlotOptions o;
  o.xMin = 2;
  o.xMax = 2;
  o.yMin = 5;
  o.yMax = 1;
  const std::vector<Series> all{line("s", {2, 2}, {1, 5})};
  const Image<Rgba8> im = renderPlot(all, o);
  EXPECT_GT(countInRect(im, plotArea(all, o), plotPalette()[0]), 20);
}

// Point labels never overlap: coincident points get one label in each of the
// four places beside the marker, and the rest none.
TEST(Plot, PointLabelsDoNotOverlap) {
  const Rgba8 ink{200, 30, 120, 255};
  auto labelled = [&](int n) {
    Series s = line("", std::vector<double>(n, 5.0), std::vector<double>(n, 5.0));
    s.lines = s.markers = false;
    s.colour = ink;
    s.pointLabels.assign(static_cast<std::size_t>(n), "2^11");
    // Spread points fixing the axes, unlabelled.
    Series frame = line("", {0, 10}, {0, 10});
    frame.lines = frame.markers = false;
    const PlotOptions o{.width = 600, .height = 400};
    const Image<Rgba8> im = renderPlot({frame, s}, o);
    return countInRect(im, plotArea({frame, s}, o), ink);
  };
  const long one = labelled(1);
  ASSERT_GT(one, 10);
  EXPECT_EQ(labelled(2), 2 * one);
  EXPECT_EQ(labelled(4), 4 * one);
  EXPECT_EQ(labelled(7), 4 * one);  // no fifth place: left out
}

}  // namespace
}  // namespace hw::report
