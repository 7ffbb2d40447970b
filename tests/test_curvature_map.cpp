// Curvature maps: the per-vertex mean curvature (curvature/mean_curvature_field.h) has the
// documented sign and size, and the `curvature` render style colours it on a diverging map
// symmetric about zero (blue negative, white 0, red positive) with a legend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "curvature/mean_curvature_field.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure {
namespace {

modeling::Mesh heightField(int n, const std::string& spec) {
  modeling::GeneratorOptions generator;
  generator.n = n;
  modeling::Mesh mesh = modeling::generateMesh(generator);
  modeling::applyHeightField(modeling::PolynomialSurface::parse(spec), mesh.positions);
  return mesh;
}

bool onBoundary(const modeling::Mesh& mesh, int v) {
  return std::abs(std::abs(mesh.positions(v, 0)) - 0.5) < 1e-12 ||
         std::abs(std::abs(mesh.positions(v, 1)) - 0.5) < 1e-12;
}

TEST(CurvatureMap, BowlIsPositiveAndSaddleHasBothSignsSymmetrically) {
  const modeling::Mesh bowl = heightField(16, "quadratic:1,0,1");  // z = x² + y²: H(0) = 2
  const std::vector<double> h = curvature::cotanVertexMeanCurvature(bowl);
  ASSERT_EQ(static_cast<int>(h.size()), bowl.vertexCount());
  for (int v = 0; v < bowl.vertexCount(); ++v) {
    if (onBoundary(bowl, v)) {
      EXPECT_EQ(h[v], 0.0);
    } else {
      EXPECT_GT(h[v], 0.0) << "vertex " << v;
    }
    if (bowl.positions.row(v).head<2>().norm() < 1e-12) {
      EXPECT_NEAR(h[v], 2.0, 0.05);
    }
  }
  // z = x² − y²: the 4-8 patch is symmetric under a quarter turn, which negates the saddle, so the
  // field's extremes are opposite.
  const modeling::Mesh saddle = heightField(16, "quadratic:1,0,-1");
  const std::vector<double> s = curvature::cotanVertexMeanCurvature(saddle);
  const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
  EXPECT_LT(*lo, -0.1);
  EXPECT_GT(*hi, 0.1);
  EXPECT_NEAR(*lo, -*hi, 1e-9 * *hi);
}

// Pixel (x, y) as r − b: > 0 reddish (positive H), < 0 bluish (negative H).
int redness(const render::Image& image, int x, int y) {
  const auto p = image.pixel(x, y);
  return int(p[0]) - int(p[2]);
}

TEST(CurvatureMap, RenderUsesADivergingMapSymmetricAboutZero) {
  render::OffscreenContext context;
  render::RenderOptions options;
  options.style = render::RenderStyle::Curvature;
  options.width = 256 + render::kLegendWidth;
  options.height = 256;
  const auto render = [&](const modeling::Mesh& mesh) {
    options.vertexScalars = curvature::cotanVertexMeanCurvature(mesh);
    return render::renderMesh(context, mesh, options);
  };
  const render::Image bowl = render(heightField(16, "quadratic:1,0,1"));
  const render::Image saddle = render(heightField(16, "quadratic:1,0,-1"));
  ASSERT_EQ(bowl.width, 256 + render::kLegendWidth);
  // The legend bar (render/legend.cpp: 14 px right of the mesh, 18 wide, from 18 % to
  // 82 % of the height): blue at the bottom (−m), white in the middle (0), red at the top (+m).
  const int barX = 256 + 14 + 9;
  EXPECT_GT(redness(bowl, barX, 50), 100);
  EXPECT_LT(redness(bowl, barX, 205), -100);
  const auto middle = bowl.pixel(barX, 128);
  EXPECT_GT(std::min({middle[0], middle[1], middle[2]}), 220);
  // Bowl: one sign, red (away from the boundary ring, which is 0). Saddle: z = x² − y² is
  // positive (red) above and below the centre (y, image up) and negative (blue) left and right.
  int bluish = 0;
  for (int y = 64; y < 192; ++y)
    for (int x = 64; x < 192; ++x) bluish += redness(bowl, x, y) < 0;
  EXPECT_EQ(bluish, 0);
  EXPECT_GT(redness(bowl, 128, 128), 100);
  EXPECT_GT(redness(saddle, 128, 30), 50);
  EXPECT_GT(redness(saddle, 128, 226), 50);
  EXPECT_LT(redness(saddle, 30, 128), -50);
  EXPECT_LT(redness(saddle, 226, 128), -50);
}

// Pixels on the image's border that differ from the (white) background.
int inkOnBorder(const render::Image& image) {
  int count = 0;
  const auto ink = [&](int x, int y) {
    const auto p = image.pixel(x, y);
    return p[0] != 255 || p[1] != 255 || p[2] != 255;
  };
  for (int x = 0; x < image.width; ++x) count += ink(x, 0) + ink(x, image.height - 1);
  for (int y = 0; y < image.height; ++y) count += ink(0, y) + ink(image.width - 1, y);
  return count;
}

// `flexure render bowl.obj --style curvature` (docs/commands/render.md's bowl) at the default size
// and at a small one: the legend's title and range line fit in the image (no ink on its border; the
// title used to run off the right edge).
TEST(CurvatureMap, LegendTextStaysInsideTheImage) {
  render::OffscreenContext context;
  const modeling::Mesh bowl = heightField(32, "quadratic:1,0,0.5");
  for (const int size : {1024, 200}) {
    render::RenderOptions options;
    options.style = render::RenderStyle::Curvature;
    options.width = size + render::kLegendWidth;
    options.height = size;
    options.scalarLabel = "mean curvature H";
    options.vertexScalars = curvature::cotanVertexMeanCurvature(bowl);
    EXPECT_EQ(inkOnBorder(render::renderMesh(context, bowl, options)), 0) << "size " << size;
  }
}

// Round ticks: multiples of a 1-2-5 step, at least four, inside the range.
TEST(CurvatureMap, LegendTicksAreRoundValues) {
  const std::vector<double> symmetric = render::legendTicks(-0.75, 0.75);
  ASSERT_EQ(symmetric.size(), 7u);  // step 0.2: -0.6 … 0.6
  for (std::size_t k = 0; k < symmetric.size(); ++k)
    EXPECT_NEAR(symmetric[k], -0.6 + 0.2 * static_cast<double>(k), 1e-12);
  const std::vector<double> error = render::legendTicks(0.0, 3.7e-4);
  ASSERT_EQ(error.size(), 4u);  // step 1e-4: 0 … 3e-4
  EXPECT_NEAR(error.back(), 3e-4, 1e-18);
  for (const auto& [lo, hi] :
       {std::pair{-267.0, 267.0}, std::pair{0.0, 1.0}, std::pair{-3.2, 3.2}}) {
    const std::vector<double> t = render::legendTicks(lo, hi);
    ASSERT_GE(t.size(), 4u);
    const double step = t[1] - t[0];
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 ||
                std::abs(mantissa - 5) < 1e-9)
        << "step " << step;
    EXPECT_GE(t.front(), lo);
    EXPECT_LE(t.back(), hi);
  }
}

// A few spikes (bunny00.off's largest |H| is 267, its 98th percentile 67.9) do not set the range:
// the default is the 98th percentile of |H|; without outliers it is the largest value.
TEST(CurvatureMap, DefaultRangeIsARobustPercentile) {
  std::vector<double> h(1000);
  for (int v = 0; v < 1000; ++v) h[v] = (v % 2 ? 1.0 : -1.0) * (v % 100) / 100.0;  // |H| < 1
  h[17] = 267.0;
  h[18] = -150.0;
  EXPECT_NEAR(render::curvatureRange(h), 0.98, 1e-12);  // 98 % of the values are ≤ 0.98
  EXPECT_EQ(render::curvatureRangeRule(h), "98th percentile");
  const std::vector<double> smooth = {0.1, -0.3, 0.75};
  EXPECT_EQ(render::curvatureRange(smooth), 0.75);
  EXPECT_EQ(render::curvatureRangeRule(smooth), "largest");
  EXPECT_EQ(render::curvatureRange(std::vector<double>(10, 0.0)), 1e-12);
}

TEST(CurvatureMap, TheRendererNeedsAValuePerVertex) {
  const modeling::Mesh bowl = heightField(4, "quadratic:1,0,1");
  render::RenderOptions options;
  options.style = render::RenderStyle::Curvature;
  options.width = 64 + render::kLegendWidth;
  options.height = 64;
  EXPECT_THROW(render::renderMesh(bowl, options), InputError);
  options.vertexScalars.assign(3, 1.0);
  EXPECT_THROW(render::renderMesh(bowl, options), InputError);
}

}  // namespace
}  // namespace flexure
