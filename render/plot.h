// Log-log plots (Cairo) for convergence studies: error against mesh size or amplitude, one series
// per energy, decade ticks, a legend and optional reference slopes. PNG out, written atomically.
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

}  // namespace flexure::render
