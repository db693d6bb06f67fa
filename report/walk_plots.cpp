#include "report/walk_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/file_io.h"
#include "report/plot.h"

namespace hw::report {

Status writeFrameTimes(const std::string& pngPath, const FrameTimesData& t, const FrameTimesLook& look) {
  Series work{"warped frame: work (ms.frame)"}, geometry{"frame drawn as geometry: work"},
      built{"frame that built/uploaded a keyframe"},
      key{"keyframe frame"}, reference{"geometry frame, same camera (reference_ms)"},
      interval{"presented interval (ms.interval)"}, budget{"budget"},
      floor{"fill floor: two layers of one full-screen quad (floor_ms)"};
  const Rgba8 kBlue{31, 119, 180, 255}, kRed{214, 39, 40, 255}, kGreen{44, 160, 44, 255},
      kGrey{110, 110, 110, 255}, kOrange{255, 127, 14, 255}, kPurple{148, 103, 189, 255},
      kBrown{140, 86, 75, 255}, kBlack{0, 0, 0, 255};
  work.colour = kBlue;
  geometry.colour = kBrown;
  built.colour = kRed;
  key.colour = kGreen;
  reference.colour = kGrey;
  interval.colour = kOrange;
  budget.colour = kPurple;
  floor.colour = kBlack;
  bool anyBudget = false;
  for (std::size_t i = 0; i < t.frame.size(); ++i) {
    const double x = t.frame[i];
    // Warped and geometry frames as lines, each broken where the other
    // kind (or a keyframe frame) sits.
    const DrawnAs k = t.kind[i];
    work.x.push_back(x);
    work.y.push_back(k == DrawnAs::Warp ? t.workMs[i] : std::nan(""));
    geometry.x.push_back(x);
    geometry.y.push_back(k == DrawnAs::Geometry ? t.workMs[i] : std::nan(""));
    if (k == DrawnAs::Keyframe) key.x.push_back(x), key.y.push_back(t.workMs[i]);
    if (t.builtKeyframe[i]) built.x.push_back(x), built.y.push_back(t.workMs[i]);
    reference.x.push_back(x);
    reference.y.push_back(t.referenceMs[i]);
    interval.x.push_back(x);
    interval.y.push_back(t.intervalMs[i]);
    if (t.floorMs > 0) floor.x.push_back(x), floor.y.push_back(t.floorMs);
    if (t.budgetMs[i] > 0) {
      anyBudget = true;
      budget.x.push_back(x);
      budget.y.push_back(t.budgetMs[i]);
    }
  }
  work.markers = false;
  geometry.markers = false;
  reference.markers = false;
  key.lines = built.lines = interval.lines = false;
  key.marker = Marker::kDiamond;
  built.marker = Marker::kSquare;
  interval.marker = Marker::kCircle;
  budget.markers = false;
  floor.markers = false;
  PlotOptions po;
  po.title = look.title;
  po.xLabel = "frame";
  po.yLabel = "ms (log)";
  po.logY = true;
  po.width = 1000;
  po.height = 480;
  std::vector<Series> series{work, key, built};
  if (look.reference) series.push_back(reference);
  // After the reference, which it equals: drawn on top of it.
  const bool anyGeometry =
      std::find(t.kind.begin(), t.kind.end(), DrawnAs::Geometry) != t.kind.end();
  if (anyGeometry) series.push_back(geometry);
  if (look.interval) series.push_back(interval);
  if (anyBudget) series.push_back(budget);
  if (!floor.x.empty()) series.push_back(floor);
  return writePlot(pngPath, series, po);
}

Status writeStrips(const std::string& outDir, const std::vector<Image<Rgba8>>& strips,
                   const nlohmann::json& info) {
  constexpr int kGap = 4;  // between the panels
  const Rgba8 kInk{20, 20, 20, 255}, kPaper{255, 255, 255, 255};
  for (std::size_t s = 0; s < strips.size() && s < info.size(); ++s) {
    const Image<Rgba8>& strip = strips[s];
    const int line = captionHeight() + 6;
    Image<Rgba8> out(strip.width(), strip.height() + 2 * line);
    out.fill(kPaper);
    for (int y = 0; y < strip.height(); ++y)
      for (int x = 0; x < strip.width(); ++x) out(x, y + 2 * line) = strip(x, y);
    const int panel = (strip.width() - 3 * kGap) / 4;
    const int frame = info[s]["frame"].get<int>();
    const char* titles[4] = {"reference (geometry)", "hybrid (warped)", "|difference| x4",
                             "holes (red)"};
    for (int p = 0; p < 4; ++p) drawCaption(out, titles[p], p * (panel + kGap) + 4, 3, kInk);
    char psnrText[32] = "identical";
    if (info[s]["psnr"].is_number())
      std::snprintf(psnrText, sizeof psnrText, "%.2f dB", info[s]["psnr"].get<double>());
    char text[160];
    std::snprintf(text, sizeof text, "frame %d   PSNR %s   SSIM %.4f   holes %.2f %%", frame,
                  psnrText, info[s]["ssim"].is_number() ? info[s]["ssim"].get<double>() : 1.0,
                  100.0 * info[s]["holes_before_fallback"].get<double>());
    drawCaption(out, text, 4, line + 3, kInk);
    HW_TRY(writePng(outDir + "/strip_" + std::to_string(frame) + ".png", out));
  }
  return {};
}

}  // namespace hw::report
