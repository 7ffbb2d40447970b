// Plots (Cairo): log-log ones for convergence studies (error against mesh size or amplitude, one
// series per energy, decade ticks, a legend and optional reference slopes) and linear ones for
// time histories. PNG out, written atomically.
#pragma once

#include <string>
#include <vector>

namespace flexure::render {

// One curve: points (x[k], y[k]) joined in the given order. Points with a non-positive or
// non-finite coordinate cannot be drawn on log axes and are left out.
struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
};

// A dashed guide y ∝ x^slope through the geometric centre of all drawn points.
struct ReferenceSlope {
  double slope = 1.0;
  std::string label;  // e.g. "slope 2"
};

struct LogLogPlot {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
  std::vector<ReferenceSlope> referenceSlopes;
  int width = 880, height = 560;  // pixels
};

// The plot as PNG bytes: title on top; each axis from the largest m × 10^k (m in {1, 2, 5}) below
// the data to the smallest above, with labelled decade ticks (and labelled 2 and 5 ticks when it
// spans at most two decades); the legend to the right of the plot area. Series take distinct
// colours and markers in order (8 of each, cycling). Throws std::invalid_argument for a size below
// 200 × 150 pixels.
std::string renderLogLogPlot(const LogLogPlot& plot);

// renderLogLogPlot written to `path` atomically (InputError naming the path when it cannot be).
void writeLogLogPlot(const LogLogPlot& plot, const std::string& path);

// The same on linear axes (a time history, say): each axis from the largest multiple of its tick
// step (1, 2 or 5 × 10^k, 4 to 10 ticks) below the data to the smallest above, every tick labelled;
// series of more than 60 points drawn as lines without markers.
struct LinePlot {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
  int width = 880, height = 560;  // pixels
};
std::string renderLinePlot(const LinePlot& plot);
void writeLinePlot(const LinePlot& plot, const std::string& path);

}  // namespace flexure::render
