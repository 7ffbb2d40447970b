// The colour maps of flexure's figures: piecewise linear on [0, 1] through equally spaced stops.
#pragma once

#include <algorithm>
#include <vector>

#include "render/mesh_renderer.h"

namespace flexure::render {

// A piecewise-linear colour map on [0, 1] through equally spaced stops.
struct ColourMap {
  std::vector<Rgb> stops;

  Rgb at(double t) const {
    const double x = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
    const std::size_t i = std::min(static_cast<std::size_t>(x), stops.size() - 2);
    const double f = x - i;
    const Rgb &a = stops[i], &b = stops[i + 1];
    return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
  }
};

// Sequential (magnitudes from 0): five samples of matplotlib's viridis, dark violet to yellow,
// monotone in lightness.
inline const ColourMap& sequentialColourMap() {
  static const ColourMap map{{{0.267, 0.005, 0.329},
                              {0.229, 0.322, 0.546},
                              {0.128, 0.567, 0.551},
                              {0.369, 0.789, 0.383},
                              {0.993, 0.906, 0.144}}};
  return map;
}

// Diverging (signed values on a range symmetric about 0): ColorBrewer's 7-class RdBu reversed,
// blue (negative) through near-white (0) to red (positive).
inline const ColourMap& divergingColourMap() {
  static const ColourMap map{{{0.129, 0.400, 0.675},
                              {0.404, 0.663, 0.812},
                              {0.820, 0.898, 0.941},
                              {0.969, 0.969, 0.969},
                              {0.992, 0.859, 0.780},
                              {0.937, 0.541, 0.384},
                              {0.698, 0.094, 0.169}}};
  return map;
}

}  // namespace flexure::render
