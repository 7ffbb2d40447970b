// The offscreen renderer (render/mesh_renderer.h), judged by its pixels: a plane seen head-on
// reflects one colour; a cylinder's reflection lines are straight and a bowl's are not; a mirror-
// symmetric mesh gives a mirror-symmetric image; a mesh on the surface has zero error; the PNG
// reads back at the requested size; a missing or broken OSMesa is a clear error.
#include <cairo.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure {
namespace {

using render::Image;
using render::RenderOptions;
using render::RenderStyle;
using testing::HasSubstr;

// A background no style paints, so that coverage can be read off the pixels.
constexpr render::Rgb kGreen{0.0, 1.0, 0.0};

modeling::Mesh squareMesh(int n) {
  modeling::GeneratorOptions generator;
  generator.family = modeling::MeshFamily::Patch48;
  generator.n = n;
  return modeling::generateMesh(generator);
}

// Part of the unit cylinder z = √(1 − x²) over the square [−½, ½]²: the axis is the y axis.
modeling::Mesh cylinderMesh(int n) {
  modeling::Mesh mesh = squareMesh(n);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const double x = mesh.positions(v, 0);
    mesh.positions(v, 2) = std::sqrt(1.0 - x * x);
  }
  return mesh;
}

modeling::Mesh heightFieldMesh(int n, const std::string& spec) {
  modeling::Mesh mesh = squareMesh(n);
  modeling::applyHeightField(modeling::PolynomialSurface::parse(spec), mesh.positions);
  return mesh;
}

RenderOptions headOn(RenderStyle style, int width = 256, int height = 256) {
  RenderOptions options;
  options.style = style;
  options.width = width;
  options.height = height;
  options.background = kGreen;
  return options;
}

bool isBackground(const Image& image, int x, int y) {
  const auto p = image.pixel(x, y);
  return p[0] == 0 && p[1] == 255 && p[2] == 0;
}

// Pixels inside the mesh's image, away from its anti-aliased silhouette: the pixel and every
// pixel within `margin` of it (in x and y) are off the background.
std::vector<std::vector<bool>> interiorMask(const Image& image, int margin = 2) {
  std::vector<std::vector<bool>> mask(image.height, std::vector<bool>(image.width, false));
  for (int y = margin; y < image.height - margin; ++y) {
    for (int x = margin; x < image.width - margin; ++x) {
      bool inside = true;
      for (int dy = -margin; dy <= margin && inside; ++dy)
        for (int dx = -margin; dx <= margin && inside; ++dx)
          inside = !isBackground(image, x + dx, y + dy);
      mask[y][x] = inside;
    }
  }
  return mask;
}

int countInterior(const std::vector<std::vector<bool>>& mask) {
  int count = 0;
  for (const auto& row : mask) count += static_cast<int>(std::count(row.begin(), row.end(), true));
  return count;
}

int channelDistance(const std::array<std::uint8_t, 4>& a, const std::array<std::uint8_t, 4>& b) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a[k]) - int(b[k])));
  return d;
}

// The largest colour spread (max − min of the grey value) along any image column over its
// interior pixels, for columns with at least 20 of them.
int largestColumnSpread(const Image& image) {
  const auto mask = interiorMask(image);
  int spread = 0;
  for (int x = 0; x < image.width; ++x) {
    int lo = 255, hi = 0, count = 0;
    for (int y = 0; y < image.height; ++y) {
      if (!mask[y][x]) continue;
      const int grey = image.pixel(x, y)[0];
      lo = std::min(lo, grey);
      hi = std::max(hi, grey);
      ++count;
    }
    if (count >= 20) spread = std::max(spread, hi - lo);
  }
  return spread;
}

TEST(Render, PlaneSeenHeadOnReflectsOneColour) {
  for (bool smooth : {true, false}) {
    RenderOptions options = headOn(RenderStyle::Reflection);
    options.smoothNormals = smooth;
    const Image image = render::renderMesh(squareMesh(8), options);
    ASSERT_EQ(image.width, 256);
    ASSERT_EQ(image.height, 256);
    const auto mask = interiorMask(image);
    ASSERT_GT(countInterior(mask), 256 * 256 / 2) << "the plane should fill most of the frame";
    std::array<std::uint8_t, 4> first{};
    bool seen = false;
    int worst = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        if (!mask[y][x]) continue;
        if (!seen) first = image.pixel(x, y), seen = true;
        worst = std::max(worst, channelDistance(first, image.pixel(x, y)));
      }
    }
    EXPECT_LE(worst, 1) << (smooth ? "smooth" : "flat") << " normals";
  }
}

// Marked faces (RenderOptions.markedFaces, the faces at an invalid mesh's problems) take the
// marking colour over every style: the left half of a square seen head-on is red, the right half
// is not; a face index that is not the mesh's is refused.
TEST(Render, MarkedFacesTakeTheMarkingColour) {
  const modeling::Mesh mesh = squareMesh(8);
  const double middle = mesh.positions.col(0).mean();
  for (RenderStyle style : {RenderStyle::Shaded, RenderStyle::Reflection}) {
    RenderOptions options = headOn(style);
    for (int f = 0; f < mesh.faceCount(); ++f) {
      double x = 0.0;
      for (int k = 0; k < 3; ++k) x += mesh.positions(mesh.triangles(f, k), 0) / 3.0;
      if (x < middle) options.markedFaces.push_back(f);
    }
    const Image image = render::renderMesh(mesh, options);
    const auto left = image.pixel(64, 128), right = image.pixel(192, 128);
    EXPECT_GT(left[0], 200) << renderStyleName(style);
    EXPECT_LT(left[1], 50) << renderStyleName(style);
    EXPECT_LT(left[2], 50) << renderStyleName(style);
    // Unmarked: the shaded grey-blue or a stripe's grey, red no more than green.
    EXPECT_LT(std::abs(int(right[0]) - int(right[1])), 40) << renderStyleName(style);
  }
  RenderOptions options = headOn(RenderStyle::Shaded);
  options.markedFaces = {mesh.faceCount()};
  EXPECT_THROW(render::renderMesh(mesh, options), InputError);
}

TEST(Render, CylinderReflectionLinesAreStraight) {
  // Axis along y (image up), vertical stripes: the reflected direction depends on x alone, so
  // every column is one colour and the stripes run straight along the axis.
  RenderOptions options = headOn(RenderStyle::Reflection);
  options.stripeDirectionDegrees = 90.0;
  const Image image = render::renderMesh(cylinderMesh(32), options);
  EXPECT_LE(largestColumnSpread(image), 6);
  // ... while across the axis the stripes alternate between dark and light.
  const auto mask = interiorMask(image);
  int lo = 255, hi = 0, changes = 0, previous = -1;
  const int y = image.height / 2;
  for (int x = 0; x < image.width; ++x) {
    if (!mask[y][x]) continue;
    const int grey = image.pixel(x, y)[0];
    lo = std::min(lo, grey);
    hi = std::max(hi, grey);
    const int level = grey > 128 ? 1 : 0;
    if (previous >= 0 && level != previous) ++changes;
    previous = level;
  }
  EXPECT_LT(lo, 40);
  EXPECT_GT(hi, 215);
  EXPECT_GE(changes, 4);

  // The same check fails on a doubly curved bowl, whose reflection lines bend.
  const Image bowl = render::renderMesh(heightFieldMesh(32, "quadratic:1,0,1"), options);
  EXPECT_GT(largestColumnSpread(bowl), 150);
}

TEST(Render, HighlightLinesOnAPlaneAreStraightAndParallel) {
  RenderOptions options = headOn(RenderStyle::Highlight);
  options.stripeDirectionDegrees = 90.0;
  const Image image = render::renderMesh(squareMesh(8), options);
  EXPECT_LE(largestColumnSpread(image), 6);
  const auto mask = interiorMask(image);
  int lo = 255, hi = 0;
  for (int x = 0; x < image.width; ++x) {
    if (!mask[image.height / 2][x]) continue;
    lo = std::min<int>(lo, image.pixel(x, image.height / 2)[0]);
    hi = std::max<int>(hi, image.pixel(x, image.height / 2)[0]);
  }
  EXPECT_LT(lo, 40);
  EXPECT_GT(hi, 215);
}

TEST(Render, MirrorSymmetricMeshGivesMirrorSymmetricImage) {
  // patch48 with even n is symmetric under x ↦ −x, and so is the height field.
  const modeling::Mesh mesh = heightFieldMesh(16, "polynomial:x^2+0.5*y^3+0.3*y-0.4*x^4");
  for (RenderStyle style : {RenderStyle::Reflection, RenderStyle::Highlight}) {
    RenderOptions options = headOn(style, 300, 240);
    options.elevationDegrees = 55.0;  // tilted about the image x axis: still symmetric
    const Image image = render::renderMesh(mesh, options);
    const auto mask = interiorMask(image);
    long total = 0;
    int worstInside = 0, worstSilhouette = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const int mirror = image.width - 1 - x;
        const int d = channelDistance(image.pixel(x, y), image.pixel(mirror, y));
        total += d;
        if (mask[y][x] && mask[y][mirror]) {
          worstInside = std::max(worstInside, d);
        } else {
          worstSilhouette = std::max(worstSilhouette, d);
        }
      }
    }
    EXPECT_LT(total / (double(image.width) * image.height), 0.5) << renderStyleName(style);
    EXPECT_LE(worstInside, 16) << renderStyleName(style);
    // Inside, only the anti-aliased stripe edges may differ a little (fwidth comes from 2 × 2
    // pixel quads, which mirroring regroups). The multisample pattern is not mirror-symmetric:
    // silhouette pixels may differ by a quarter of the green-to-mesh contrast (≤ 64 levels).
    EXPECT_LE(worstSilhouette, 70) << renderStyleName(style);
  }
  // An asymmetric mesh is told apart.
  const Image skew = render::renderMesh(heightFieldMesh(16, "polynomial:x^2+0.4*x^3+0.3*y"),
                                        headOn(RenderStyle::Reflection, 300, 240));
  long total = 0;
  for (int y = 0; y < skew.height; ++y)
    for (int x = 0; x < skew.width; ++x)
      total += channelDistance(skew.pixel(x, y), skew.pixel(skew.width - 1 - x, y));
  EXPECT_GT(total / (double(skew.width) * skew.height), 5.0);
}

TEST(Render, MeshOnTheSurfaceHasOneErrorColour) {
  const std::string spec = "quadratic:1,0.5,-1";
  const modeling::Mesh mesh = heightFieldMesh(16, spec);
  RenderOptions options = headOn(RenderStyle::Error, 400, 256);
  options.surface = modeling::PolynomialSurface::parse(spec);
  const Image image = render::renderMesh(mesh, options);
  ASSERT_EQ(image.width, 400);
  const auto mask = interiorMask(image);
  const std::array<std::uint8_t, 4> zeroColour{68, 1, 84, 255};  // the colour map at 0
  int worst = 0, covered = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width - render::kLegendWidth; ++x) {
      if (!mask[y][x]) continue;
      ++covered;
      worst = std::max(worst, channelDistance(zeroColour, image.pixel(x, y)));
    }
  }
  EXPECT_GT(covered, 10000);
  EXPECT_LE(worst, 1);
  EXPECT_EQ(render::vertexSurfaceErrors(mesh, options.surface),
            std::vector<double>(mesh.vertexCount(), 0.0));

  // Against another surface the colours spread over the map.
  options.surface = modeling::PolynomialSurface::parse("quadratic:0,0,0");
  const Image off = render::renderMesh(mesh, options);
  const auto offMask = interiorMask(off);
  int spread = 0;
  for (int y = 0; y < off.height; ++y)
    for (int x = 0; x < off.width - render::kLegendWidth; ++x)
      if (offMask[y][x]) spread = std::max(spread, channelDistance(zeroColour, off.pixel(x, y)));
  EXPECT_GT(spread, 150);
}

TEST(Render, EveryStyleRendersAndOptionsChangeThePicture) {
  const modeling::Mesh mesh = heightFieldMesh(8, "quadratic:1,0,0.5");
  RenderOptions options = headOn(RenderStyle::Shaded, 128, 96);
  options.elevationDegrees = 50.0;
  options.azimuthDegrees = 30.0;
  const Image shaded = render::renderMesh(mesh, options);
  EXPECT_GT(countInterior(interiorMask(shaded)), 1000);
  options.smoothNormals = false;
  EXPECT_NE(render::renderMesh(mesh, options).rgba, shaded.rgba) << "flat normals";
  options.smoothNormals = true;
  options.edges = true;
  EXPECT_NE(render::renderMesh(mesh, options).rgba, shaded.rgba) << "edge overlay";
  options.edges = false;
  options.projection = render::Projection::Perspective;
  EXPECT_NE(render::renderMesh(mesh, options).rgba, shaded.rgba) << "perspective";
  options.projection = render::Projection::Orthographic;
  options.style = RenderStyle::Isophote;
  EXPECT_NE(render::renderMesh(mesh, options).rgba, shaded.rgba) << "isophote";
  // The same input renders to the same pixels.
  options.style = RenderStyle::Shaded;
  EXPECT_EQ(render::renderMesh(mesh, options).rgba, shaded.rgba);
}

// The outline colour (RenderOptions::outlineColour, 0, 0.8, 0.2), to within the anti-aliasing of
// the stroke's edge: the pixels a stroke covers fully.
bool isOutline(const Image& image, int x, int y) {
  const auto p = image.pixel(x, y);
  return p[0] <= 8 && std::abs(p[1] - 204) <= 8 && std::abs(p[2] - 51) <= 8;
}

int countOutline(const Image& image, int x0, int x1) {
  int count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = x0; x < x1; ++x) count += isOutline(image, x, y);
  return count;
}

// An outline segment lands where the camera projects it, over every style, legend or not: the
// unit square seen head-on fills [−½, ½]² × 1.06 of the (square) frame, so the segment from
// (−¼, 0) to (¼, 0) crosses the image's middle row over about half of the framed width.
TEST(Render, OutlineIsDrawnWhereTheCameraProjectsIt) {
  const modeling::Mesh plane = squareMesh(8);
  for (const RenderStyle style : {RenderStyle::Reflection, RenderStyle::Curvature}) {
    RenderOptions options = headOn(style, 256 + (style == RenderStyle::Curvature ? 130 : 0), 256);
    options.vertexScalars.assign(plane.vertexCount(), 0.0);
    const Image plain = render::renderMesh(plane, options);
    EXPECT_EQ(countOutline(plain, 0, plain.width), 0) << renderStyleName(style);
    options.outlineSegments.resize(2, 3);
    options.outlineSegments << -0.25, 0.0, 0.0, 0.25, 0.0, 0.0;
    const Image outlined = render::renderMesh(plane, options);
    const int framed = 256;  // the mesh's part of the image (the legend is to its right)
    const double length = 0.5 / 1.06 * framed;  // pixels
    const int count = countOutline(outlined, 0, framed);
    EXPECT_GT(count, 1.5 * length) << renderStyleName(style);
    EXPECT_LT(count, 3.5 * length) << renderStyleName(style);
    EXPECT_TRUE(isOutline(outlined, framed / 2, framed / 2)) << renderStyleName(style);
    EXPECT_TRUE(isOutline(outlined, framed / 2 + static_cast<int>(0.45 * length), framed / 2));
    EXPECT_FALSE(isOutline(outlined, framed / 2 + static_cast<int>(0.55 * length), framed / 2));
    EXPECT_FALSE(isOutline(outlined, framed / 2, framed / 2 + 8)) << renderStyleName(style);
    EXPECT_EQ(countOutline(outlined, framed, outlined.width), 0) << "the legend stays clean";
  }
  RenderOptions bad = headOn(RenderStyle::Reflection);
  bad.outlineSegments.resize(3, 3);
  bad.outlineSegments.setZero();
  EXPECT_THROW(render::renderMesh(plane, bad), InputError);
}

// The unit square cut along x = 0 from its lower edge up to the tip (0, tipY), as a fracture cuts
// (modeling/crack_cut.h): the faces right of the line take copies of its vertices below the tip,
// at the same positions, so the two sides share no edge there and the tip vertex stays whole.
modeling::Mesh squareCutBelow(double tipY) {
  modeling::Mesh mesh = squareMesh(8);
  const int original = mesh.vertexCount();
  std::vector<int> copyOf(original, -1);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    double x = 0.0;
    for (int k = 0; k < 3; ++k) x += mesh.positions(mesh.triangles(f, k), 0) / 3.0;
    if (x < 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      if (v >= original || mesh.positions(v, 0) != 0.0 || mesh.positions(v, 1) >= tipY) continue;
      if (copyOf[v] < 0) {
        copyOf[v] = mesh.vertexCount();
        mesh.positions.conservativeResize(mesh.vertexCount() + 1, 3);
        mesh.positions.row(copyOf[v]) = mesh.positions.row(v);
      }
      mesh.triangles(f, k) = copyOf[v];
    }
  }
  return mesh;
}

// The crack colour (RenderOptions::crackColour, magenta 1, 0, 0.8), to within the blending of the
// band's edge.
bool isCrack(const Image& image, int x, int y) {
  const auto p = image.pixel(x, y);
  return p[0] >= 200 && p[1] <= 60 && p[2] >= 150;
}

// A cut's lips are the boundary edges with a twin at the same rest positions: the 6 segments of
// x = 0 below the tip (0, 0.25), twice (the tip's two edges included), and none of the outer
// boundary; an uncut mesh has none.
TEST(Render, CrackLipsAreTheTwinnedBoundaryEdges) {
  const modeling::Mesh cut = squareCutBelow(0.25);
  const auto lips = render::crackLipEdges(cut.positions, cut.triangles);
  ASSERT_EQ(lips.size(), 12u);
  for (const auto& [a, b] : lips) {
    EXPECT_EQ(cut.positions(a, 0), 0.0);
    EXPECT_EQ(cut.positions(b, 0), 0.0);
    EXPECT_LE(std::max(cut.positions(a, 1), cut.positions(b, 1)), 0.25);
  }
  const modeling::Mesh whole = squareMesh(8);
  EXPECT_TRUE(render::crackLipEdges(whole.positions, whole.triangles).empty());
}

// The lips are drawn in the crack colour over every style, legend or not: the square cut along
// x = 0 below y = 0.25, seen head-on, has crack pixels on the image's middle columns from the
// bottom of the framed square up to the tip and nowhere else; without crackEdges it has none; an
// edge that is not the mesh's is refused.
TEST(Render, CrackEdgesAreDrawnWhereTheCrackIs) {
  const modeling::Mesh cut = squareCutBelow(0.25);
  for (const RenderStyle style :
       {RenderStyle::Shaded, RenderStyle::Reflection, RenderStyle::Plastic}) {
    const int framed = 256;  // the mesh's part of the image (the legend is to its right)
    RenderOptions options = headOn(style, framed + (style == RenderStyle::Plastic ? 130 : 0), 256);
    for (int v = 0; v < cut.vertexCount(); ++v)
      options.vertexScalars.push_back(0.5 + cut.positions(v, 0));
    int plain = 0;
    const Image uncracked = render::renderMesh(cut, options);
    for (int y = 0; y < uncracked.height; ++y)
      for (int x = 0; x < uncracked.width; ++x) plain += isCrack(uncracked, x, y);
    EXPECT_EQ(plain, 0) << renderStyleName(style);

    options.crackEdges = render::crackLipEdges(cut.positions, cut.triangles);
    const Image image = render::renderMesh(cut, options);
    // y̅ ↦ row 128 − y̅ · 256 / 1.06: the lower edge at row 249, the tip at row 68.
    const auto row = [&](double y) {
      return static_cast<int>(std::lround(128.0 - y * 256 / 1.06));
    };
    for (int y = row(0.22); y <= row(-0.45); ++y)
      EXPECT_TRUE(isCrack(image, 127, y) && isCrack(image, 128, y))
          << renderStyleName(style) << ", row " << y;
    int stray = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        stray += isCrack(image, x, y) && (std::abs(x - 127.5) > 4.0 || y < row(0.25) - 3);
    EXPECT_EQ(stray, 0) << renderStyleName(style) << ": crack pixels off the crack";
  }
  RenderOptions options = headOn(RenderStyle::Shaded);
  options.crackEdges = {{0, 80}};
  EXPECT_THAT([&] { render::renderMesh(squareMesh(8), options); },
              testing::ThrowsMessage<InputError>(HasSubstr("RenderOptions.crackEdges")));
}

TEST(Render, PngReadsBackAtTheRequestedSize) {
  const modeling::Mesh mesh = heightFieldMesh(8, "quadratic:1,0,1");
  const Image image = render::renderMesh(mesh, headOn(RenderStyle::Reflection, 200, 120));
  const std::string path = std::string(FLEXURE_TEST_TMP) + "/render_reflection.png";
  std::filesystem::remove(path);
  render::writePng(path, image);
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> png(
      cairo_image_surface_create_from_png(path.c_str()), cairo_surface_destroy);
  ASSERT_EQ(cairo_surface_status(png.get()), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(png.get()), 200);
  EXPECT_EQ(cairo_image_surface_get_height(png.get()), 120);
  // The centre pixel survives the round trip (RGB24 words are 0x00RRGGBB).
  const auto* data = cairo_image_surface_get_data(png.get());
  const int stride = cairo_image_surface_get_stride(png.get());
  const auto word = *reinterpret_cast<const std::uint32_t*>(data + 60 * stride + 4 * 100);
  const auto p = image.pixel(100, 60);
  EXPECT_EQ((word >> 16) & 0xff, p[0]);
  EXPECT_EQ((word >> 8) & 0xff, p[1]);
  EXPECT_EQ(word & 0xff, p[2]);
  EXPECT_EQ(render::encodePng(image), render::encodePng(image));
  // A directory that does not exist: InputError naming it, nothing written.
  EXPECT_THROW(render::writePng(std::string(FLEXURE_TEST_TMP) + "/no/such/dir/x.png", image),
               InputError);
}

TEST(Render, MissingOrBrokenOSMesaIsAClearError) {
  try {
    render::OffscreenContext context("/nonexistent/libOSMesa.so.8");
    FAIL() << "a missing library should throw";
  } catch (const render::RenderError& e) {
    EXPECT_THAT(e.what(), HasSubstr("OSMesa"));
    EXPECT_THAT(e.what(), HasSubstr("cannot load /nonexistent/libOSMesa.so.8"));
    EXPECT_THAT(e.what(), HasSubstr("libosmesa6"));
  }
  // A real library that is not OSMesa.
  try {
    render::OffscreenContext context("libm.so.6");
    FAIL() << "a library without OSMesa should throw";
  } catch (const render::RenderError& e) {
    EXPECT_THAT(e.what(), HasSubstr("OSMesa"));
    EXPECT_THAT(e.what(), HasSubstr("does not export OSMesaCreateContextAttribs"));
  }
  // RenderError is an InputError: the CLI exits 2 with the message.
  static_assert(std::is_base_of_v<InputError, render::RenderError>);
  // The working library gives a GL 4.5 core context.
  render::OffscreenContext context;
  EXPECT_THAT(context.description(), HasSubstr("4.5"));
}

TEST(Render, BadOptionsAreInputErrors) {
  const modeling::Mesh mesh = squareMesh(4);
  const auto rejects = [&](auto change) {
    RenderOptions options = headOn(RenderStyle::Reflection, 64, 64);
    change(options);
    EXPECT_THROW(render::renderMesh(mesh, options), InputError);
  };
  rejects([](RenderOptions& o) { o.width = 8; });
  rejects([](RenderOptions& o) { o.height = 100000; });
  rejects([](RenderOptions& o) { o.stripeWidth = 1.5; });
  rejects([](RenderOptions& o) { o.stripeCount = 0; });
  rejects([](RenderOptions& o) { o.elevationDegrees = 120.0; });
  rejects([](RenderOptions& o) { o.lightDirection = {0.0, 0.0, 0.0}; });
  rejects([](RenderOptions& o) { o.style = RenderStyle::Error; });  // 64 px: no room for legend
  EXPECT_THROW(render::parseRenderStyle("curvy"), InputError);
  EXPECT_NO_THROW(RenderOptions().validate());
  const auto message = [](auto change) {
    RenderOptions options;
    change(options);
    try {
      options.validate();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(message([](RenderOptions& o) { o.stripeWidth = 1.5; }),
              ::testing::StartsWith("RenderOptions.stripeWidth "));
  EXPECT_THAT(message([](RenderOptions& o) { o.elevationDegrees = 120.0; }),
              ::testing::StartsWith("RenderOptions.elevationDegrees "));
  EXPECT_THAT(message([](RenderOptions& o) { o.width = 8; }),
              ::testing::StartsWith("RenderOptions.width x RenderOptions.height = 8 x 1024 "));
  EXPECT_THAT(message([](RenderOptions& o) {
                o.outlineColour = {2.0, 0.0, 0.0};
              }),
              ::testing::StartsWith("RenderOptions.outlineColour: "));
  EXPECT_EQ(render::parseRenderStyle("isophote"), RenderStyle::Isophote);
  EXPECT_THAT([] { render::parseBackground("#12345"); },
              ::testing::ThrowsMessage<InputError>(
                  ::testing::StartsWith("RenderOptions.background: colour '#12345'")));
  EXPECT_THROW(render::parseBackground("#12345g"), InputError);
  const render::Rgb c = render::parseBackground("#ff8000");
  EXPECT_DOUBLE_EQ(c.r, 1.0);
  EXPECT_DOUBLE_EQ(c.g, 128.0 / 255.0);
  EXPECT_DOUBLE_EQ(c.b, 0.0);
}

// The obstacle colour (RenderOptions::obstacleColour, lit): warm, red above green above blue.
bool isObstacle(const Image& image, int x, int y) {
  const auto p = image.pixel(x, y);
  return p[0] > p[1] + 30 && p[1] > p[2] + 30 && p[0] > 120;
}

// A sphere beside the unit square, seen from above: the framed points span x ∈ [−½, 1.3] and
// y ∈ [−½, ½], so the sphere's centre (1, 0, 0) projects to x = (0.6 / (1.06 · 0.9) + 1) / 2 of
// the width, on the middle row; a floor under the square shows around it.
TEST(Render, ObstaclesAreDrawnWhereTheyProject) {
  const modeling::Mesh plane = squareMesh(8);
  RenderOptions options = headOn(RenderStyle::Shaded, 256, 256);
  const int sphereX = static_cast<int>((0.6 / (1.06 * 0.9) + 1.0) / 2.0 * 256);
  const Image without = render::renderMesh(plane, options);
  options.spheres.push_back({Eigen::Vector3d(1.0, 0.0, 0.0), 0.3});
  const Image with = render::renderMesh(plane, options);
  EXPECT_FALSE(isObstacle(without, 128, 128));
  EXPECT_TRUE(isObstacle(with, sphereX, 128));
  EXPECT_TRUE(isBackground(with, sphereX, 128 - static_cast<int>(0.45 / (1.06 * 0.9) * 128)));
  EXPECT_FALSE(isObstacle(with, 100, 128)) << "the square stays the surface colour";

  RenderOptions floor = headOn(RenderStyle::Reflection, 256, 256);
  floor.planes.push_back({Eigen::Vector3d(0.0, 0.0, 2.0), -0.4});  // z = −0.2
  const Image floored = render::renderMesh(plane, floor);
  EXPECT_FALSE(isObstacle(floored, 128, 128)) << "the square hides the floor under it";
  EXPECT_TRUE(isObstacle(floored, 12, 128)) << "the floor shows beyond the square";
  floor.spheres.push_back({Eigen::Vector3d(0.0, 0.0, 0.0), -1.0});
  EXPECT_THROW(render::renderMesh(plane, floor), InputError);
}

// The plastic style: all-zero strains take the colour map's colour of 0 everywhere; a strain at
// one vertex shows up; without the per-vertex values the options are refused, and parseRenderStyle
// does not name the style (only simulate's frames have the values).
TEST(Render, PlasticStyleColoursThePerVertexStrain) {
  const modeling::Mesh mesh = heightFieldMesh(12, "quadratic:0.5,0,0.5");
  RenderOptions options = headOn(RenderStyle::Plastic, 386, 256);
  EXPECT_THROW(render::renderMesh(mesh, options), InputError);
  options.vertexScalars.assign(static_cast<size_t>(mesh.vertexCount()), 0.0);
  const Image zero = render::renderMesh(mesh, options);
  const auto mask = interiorMask(zero);
  const std::array<std::uint8_t, 4> zeroColour{68, 1, 84, 255};
  int worst = 0;
  for (int y = 0; y < zero.height; ++y)
    for (int x = 0; x < zero.width - render::kLegendWidth; ++x)
      if (mask[y][x]) worst = std::max(worst, channelDistance(zeroColour, zero.pixel(x, y)));
  EXPECT_GT(countInterior(mask), 10000);
  EXPECT_LE(worst, 1);
  options.vertexScalars[static_cast<size_t>(mesh.vertexCount() / 2)] = 1.0;
  const Image one = render::renderMesh(mesh, options);
  int spread = 0;
  for (int y = 0; y < one.height; ++y)
    for (int x = 0; x < one.width - render::kLegendWidth; ++x)
      if (mask[y][x]) spread = std::max(spread, channelDistance(zeroColour, one.pixel(x, y)));
  EXPECT_GT(spread, 50);
  EXPECT_THROW(render::parseRenderStyle("plastic"), InputError);
  EXPECT_EQ(render::renderStyleName(RenderStyle::Plastic), "plastic");
}

// Displacement from the mesh itself is 0 everywhere: one colour, the map's colour of 0; from a
// lifted copy the colours spread; an exaggerated render draws x̄ + k (x − x̄).
TEST(Render, DisplacementAgainstItselfIsUniform) {
  const modeling::Mesh mesh = heightFieldMesh(12, "quadratic:0.5,0,0.5");
  RenderOptions options = headOn(RenderStyle::Displacement, 386, 256);
  options.referencePositions = mesh.positions;
  const Image same = render::renderMesh(mesh, options);
  const auto mask = interiorMask(same);
  const std::array<std::uint8_t, 4> zeroColour{68, 1, 84, 255};
  int worst = 0;
  for (int y = 0; y < same.height; ++y)
    for (int x = 0; x < same.width - render::kLegendWidth; ++x)
      if (mask[y][x]) worst = std::max(worst, channelDistance(zeroColour, same.pixel(x, y)));
  EXPECT_GT(countInterior(mask), 10000);
  EXPECT_LE(worst, 1);

  modeling::Mesh flat = squareMesh(12);
  options.referencePositions = flat.positions;
  EXPECT_EQ(render::vertexDisplacements(mesh.positions, flat.positions).size(),
            static_cast<size_t>(mesh.vertexCount()));
  const Image lifted = render::renderMesh(mesh, options);
  const auto liftedMask = interiorMask(lifted);
  int spread = 0;
  for (int y = 0; y < lifted.height; ++y)
    for (int x = 0; x < lifted.width - render::kLegendWidth; ++x)
      if (liftedMask[y][x])
        spread = std::max(spread, channelDistance(zeroColour, lifted.pixel(x, y)));
  EXPECT_GT(spread, 150);

  RenderOptions shaded = headOn(RenderStyle::Shaded, 128, 128);
  shaded.elevationDegrees = 20.0;
  shaded.referencePositions = flat.positions;
  const Image once = render::renderMesh(mesh, shaded);
  shaded.exaggeration = 3.0;
  EXPECT_NE(render::renderMesh(mesh, shaded).rgba, once.rgba) << "exaggerated";

  options.referencePositions = squareMesh(8).positions;
  EXPECT_THROW(render::renderMesh(mesh, options), InputError) << "another vertex count";
  options.referencePositions.resize(0, 3);
  EXPECT_THROW(render::renderMesh(mesh, options), InputError) << "no reference";
}

// One scale for a figure: panels with errors 1e-12 and 1e-3 get a log scale, on which they take
// different colours (each on its own scale both would be the top colour).
TEST(Render, SharedErrorScaleSeparatesPanelsDecadesApart) {
  const std::string spec = "quadratic:1,0,1";
  const auto offBy = [&](double error) {
    modeling::Mesh mesh = heightFieldMesh(8, spec);
    mesh.positions.col(2).array() += error;
    return mesh;
  };
  const modeling::Mesh tiny = offBy(1e-12), large = offBy(1e-3);
  RenderOptions options = headOn(RenderStyle::Error, 386, 256);
  options.surface = modeling::PolynomialSurface::parse(spec);
  const render::ErrorScale scale =
      render::sharedErrorScale({render::vertexSurfaceErrors(tiny, options.surface),
                                render::vertexSurfaceErrors(large, options.surface)});
  EXPECT_NEAR(scale.errorMax, 1e-3, 1e-12);
  ASSERT_TRUE(scale.errorLogFloor.has_value());
  EXPECT_LT(*scale.errorLogFloor, 1e-12);
  const auto centreColour = [&](const modeling::Mesh& mesh, const RenderOptions& o) {
    return render::renderMesh(mesh, o).pixel(128, 128);
  };
  EXPECT_LE(channelDistance(centreColour(tiny, options), centreColour(large, options)), 2)
      << "each panel on its own scale: both at the top of it";
  options.errorMax = scale.errorMax;
  options.errorLogFloor = scale.errorLogFloor;
  EXPECT_GT(channelDistance(centreColour(tiny, options), centreColour(large, options)), 100);

  // Panels within two decades stay on a linear scale.
  EXPECT_FALSE(render::sharedErrorScale({{0.0, 1e-3}, {2e-2}}).errorLogFloor.has_value());
  EXPECT_NEAR(render::sharedErrorScale({{0.0, 1e-3}, {2e-2}}).errorMax, 2e-2, 1e-15);
}

// The zero contour of a curvature-style field (a mode's nodal line) is dark where the field
// changes sign and nowhere else; a caption puts ink at the top left.
TEST(Render, ZeroContourAndCaption) {
  const modeling::Mesh plane = squareMesh(16);
  RenderOptions options = headOn(RenderStyle::Curvature, 386, 256);
  for (int v = 0; v < plane.vertexCount(); ++v)
    options.vertexScalars.push_back(plane.positions(v, 0));
  const Image plain = render::renderMesh(plane, options);
  options.zeroContour = true;
  const Image contoured = render::renderMesh(plane, options);
  const auto dark = [](const Image& image, int x, int y) {
    const auto p = image.pixel(x, y);
    return p[0] < 40 && p[1] < 40 && p[2] < 40;
  };
  EXPECT_FALSE(dark(plain, 128, 128));
  EXPECT_TRUE(dark(contoured, 128, 128));
  EXPECT_TRUE(dark(contoured, 128, 60));
  EXPECT_FALSE(dark(contoured, 140, 128));
  EXPECT_FALSE(dark(contoured, 60, 128));

  RenderOptions captioned = headOn(RenderStyle::Shaded, 256, 256);
  const Image bare = render::renderMesh(plane, captioned);
  captioned.caption = "t = 0.50 s";
  const Image withText = render::renderMesh(plane, captioned);
  int ink = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 120; ++x)
      ink += channelDistance(withText.pixel(x, y), bare.pixel(x, y)) > 100;
  EXPECT_GT(ink, 30);
}

}  // namespace
}  // namespace flexure
