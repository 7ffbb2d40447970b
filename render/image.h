// An 8-bit RGBA image, rows top to bottom: what the renderer produces and figures compose.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace flexure::render {

// RGBA, 8 bits per channel, rows top to bottom: pixel (x, y) is rgba[4 * (y * width + x) + k].
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;

  std::array<std::uint8_t, 4> pixel(int x, int y) const {
    const std::size_t i = 4 * (static_cast<std::size_t>(y) * width + x);
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
};

}  // namespace flexure::render
