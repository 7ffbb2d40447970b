#include "modeling/polynomial_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "modeling/errors.h"
#include "modeling/generators.h"

namespace flexure::modeling {
namespace {

const std::vector<Eigen::Vector2d> kSamplePoints = {
    {0.0, 0.0}, {0.3, -0.2}, {-0.5, 0.5}, {0.41, 0.17}, {-0.13, -0.37}};

void expectSameTerms(const PolynomialSurface& a, const PolynomialSurface& b) {
  ASSERT_EQ(a.terms().size(), b.terms().size());
  for (std::size_t k = 0; k < a.terms().size(); ++k) {
    EXPECT_EQ(a.terms()[k].coefficient, b.terms()[k].coefficient) << "term " << k;
    EXPECT_EQ(std::signbit(a.terms()[k].coefficient), std::signbit(b.terms()[k].coefficient));
    EXPECT_EQ(a.terms()[k].xPower, b.terms()[k].xPower) << "term " << k;
    EXPECT_EQ(a.terms()[k].yPower, b.terms()[k].yPower) << "term " << k;
  }
}

// The InputError message of parse(spec); fails the test when none is thrown.
std::string parseError(const std::string& spec) {
  try {
    PolynomialSurface::parse(spec);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError for '" << spec << "'";
  return "";
}

TEST(PolynomialSurfaceQuadratic, ValuesGradientAndHessian) {
  const double a = 1.5, b = -0.7, c = 0.25;
  const PolynomialSurface surface = PolynomialSurface::quadratic(a, b, c);
  Eigen::Matrix2d expectedHessian;
  expectedHessian << 2 * a, b, b, 2 * c;
  for (const Eigen::Vector2d& p : kSamplePoints) {
    const double x = p.x(), y = p.y();
    EXPECT_NEAR(surface.height(x, y), a * x * x + b * x * y + c * y * y, 1e-15);
    EXPECT_NEAR(surface.gradient(x, y).x(), 2 * a * x + b * y, 1e-15);
    EXPECT_NEAR(surface.gradient(x, y).y(), b * x + 2 * c * y, 1e-15);
    EXPECT_EQ(surface.hessian(x, y), expectedHessian);
  }
}

TEST(PolynomialSurfaceQuadratic, ParsedSpecMatchesFactory) {
  const PolynomialSurface parsed = PolynomialSurface::parse("quadratic: 1.5, -0.7 ,+2.5e-1 ");
  expectSameTerms(parsed, PolynomialSurface::quadratic(1.5, -0.7, 0.25));
  EXPECT_EQ(parsed.spec(), "quadratic:1.5,-0.7,0.25");
}

TEST(PolynomialSurfaceCubic, DerivativesMatchCentralDifferences) {
  const PolynomialSurface surface =
      PolynomialSurface::parse("polynomial:x^3-3*x*y^2 + 0.5*x^2*y + y - 2 + 3e-2*y^4");
  const double h = 1e-5;
  for (const Eigen::Vector2d& p : kSamplePoints) {
    const double x = p.x(), y = p.y();
    const Eigen::Vector2d g = surface.gradient(x, y);
    EXPECT_NEAR(g.x(), (surface.height(x + h, y) - surface.height(x - h, y)) / (2 * h), 1e-9);
    EXPECT_NEAR(g.y(), (surface.height(x, y + h) - surface.height(x, y - h)) / (2 * h), 1e-9);
    const Eigen::Matrix2d hessian = surface.hessian(x, y);
    const Eigen::Vector2d dx = (surface.gradient(x + h, y) - surface.gradient(x - h, y)) / (2 * h);
    const Eigen::Vector2d dy = (surface.gradient(x, y + h) - surface.gradient(x, y - h)) / (2 * h);
    EXPECT_NEAR(hessian(0, 0), dx.x(), 1e-8);
    EXPECT_NEAR(hessian(0, 1), dy.x(), 1e-8);
    EXPECT_NEAR(hessian(1, 0), dx.y(), 1e-8);
    EXPECT_NEAR(hessian(1, 1), dy.y(), 1e-8);
    EXPECT_EQ(hessian(0, 1), hessian(1, 0));
  }
}

TEST(PolynomialSurfaceCubic, ExactValuesOfTheMonkeySaddle) {
  const PolynomialSurface surface = PolynomialSurface::parse("polynomial:x^3-3*x*y^2");
  const double x = 0.3, y = -0.2;
  EXPECT_NEAR(surface.height(x, y), x * x * x - 3 * x * y * y, 1e-16);
  EXPECT_NEAR(surface.gradient(x, y).x(), 3 * x * x - 3 * y * y, 1e-15);
  EXPECT_NEAR(surface.gradient(x, y).y(), -6 * x * y, 1e-15);
  EXPECT_NEAR(surface.hessian(x, y)(0, 0), 6 * x, 1e-15);
  EXPECT_NEAR(surface.hessian(x, y)(0, 1), -6 * y, 1e-15);
  EXPECT_NEAR(surface.hessian(x, y)(1, 1), -6 * x, 1e-15);
}

TEST(PolynomialSurfaceNormal, UnitUpwardAndOrthogonalToTangents) {
  const PolynomialSurface surface = PolynomialSurface::parse("polynomial:x^3-3*x*y^2+2*x*y");
  for (const Eigen::Vector2d& p : kSamplePoints) {
    const Eigen::Vector3d normal = surface.unitNormal(p.x(), p.y());
    const Eigen::Vector2d g = surface.gradient(p.x(), p.y());
    EXPECT_NEAR(normal.norm(), 1.0, 1e-15);
    EXPECT_GT(normal.z(), 0.0);
    EXPECT_NEAR(normal.dot(Eigen::Vector3d(1.0, 0.0, g.x())), 0.0, 1e-15);
    EXPECT_NEAR(normal.dot(Eigen::Vector3d(0.0, 1.0, g.y())), 0.0, 1e-15);
  }
  EXPECT_EQ(PolynomialSurface().unitNormal(0.1, 0.2), Eigen::Vector3d(0.0, 0.0, 1.0));
}

TEST(PolynomialSurfaceParse, MonomialsAsWritten) {
  const PolynomialSurface surface = PolynomialSurface::parse("polynomial: 0.5*x^2*y + y -2*x*x");
  expectSameTerms(surface, PolynomialSurface({{0.5, 2, 1}, {1.0, 0, 1}, {-2.0, 2, 0}}));
  expectSameTerms(PolynomialSurface::parse("polynomial:-2"), PolynomialSurface({{-2.0, 0, 0}}));
  expectSameTerms(PolynomialSurface::parse("polynomial:x*y"), PolynomialSurface({{1.0, 1, 1}}));
  expectSameTerms(PolynomialSurface::parse("polynomial:3e-2*y^4"),
                  PolynomialSurface({{0.03, 0, 4}}));
  expectSameTerms(PolynomialSurface::parse("polynomial:.5 * x ^ 2 * 4"),
                  PolynomialSurface({{2.0, 2, 0}}));
}

TEST(PolynomialSurfaceParse, SpecRoundTrip) {
  const std::vector<PolynomialSurface> surfaces = {
      PolynomialSurface::quadratic(1.0, 0.0, -0.5),
      PolynomialSurface::quadratic(0.1, 1.0 / 3.0, -1e-300),
      PolynomialSurface({{1.0, 3, 0}, {-3.0, 1, 2}}),
      PolynomialSurface({{0.1, 1, 0}, {1e20, 0, 1}, {-1.0, 1, 1}, {-0.0, 0, 0}}),
      PolynomialSurface({{1.0, 1, 0}, {1.0, 1, 0}}),               // repeated terms stay separate
      PolynomialSurface({{2.0, 0, 2}, {1.0, 1, 1}, {3.0, 2, 0}}),  // not in quadratic() order
      PolynomialSurface({{1.0, 0, 0}, {-1.0, 0, 0}, {5e-324, 7, 0}}),
  };
  for (const PolynomialSurface& surface : surfaces) {
    SCOPED_TRACE(surface.spec());
    expectSameTerms(PolynomialSurface::parse(surface.spec()), surface);
  }
  EXPECT_EQ(PolynomialSurface::quadratic(1.0, 0.0, -0.5).spec(), "quadratic:1,0,-0.5");
  EXPECT_EQ(PolynomialSurface({{1.0, 3, 0}, {-3.0, 1, 2}}).spec(), "polynomial:x^3-3*x*y^2");
  for (const char* spec : {"polynomial:x^3-3*x*y^2", "polynomial:0.5*x^2*y+y", "polynomial:-2",
                           "quadratic:0.1,0.2,0.3"}) {
    EXPECT_EQ(PolynomialSurface::parse(spec).spec(), spec);
  }
  EXPECT_EQ(PolynomialSurface().spec(), "polynomial:0");
  EXPECT_EQ(PolynomialSurface::parse(PolynomialSurface().spec()).height(0.3, 0.4), 0.0);
}

TEST(PolynomialSurfaceParse, BadSpecsThrow) {
  const std::string expected = "; expected quadratic:a,b,c or polynomial:x^3-3*x*y^2";
  for (const std::string spec : {"",
                                 "x^2",
                                 "cubic:1,2",
                                 "quadratic:1,2",
                                 "quadratic:1,2,3,4",
                                 "quadratic:1,,3",
                                 "quadratic:a,b,c",
                                 "quadratic:1,2,3x",
                                 "polynomial:",
                                 "polynomial:  ",
                                 "polynomial:x+",
                                 "polynomial:2x",
                                 "polynomial:x^-1",
                                 "polynomial:x^2.5",
                                 "polynomial:x^",
                                 "polynomial:z",
                                 "polynomial:x**2",
                                 "polynomial:x^2^3",
                                 "polynomial:1e999*x",
                                 "polynomial:--x",
                                 "polynomial:nan",
                                 "polynomial:inf*x",
                                 "polynomial:x^1000",
                                 "polynomial:(x+y)"}) {
    const std::string message = parseError(spec);
    EXPECT_EQ(message.rfind("bad surface '" + spec + "': ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
  EXPECT_NE(parseError("quadratic:1,2").find("exactly 3 numbers"), std::string::npos);
  EXPECT_NE(parseError("quadratic:1,x,3").find("b = 'x' is not a number"), std::string::npos);
  EXPECT_NE(parseError("polynomial:x+z").find("'z'"), std::string::npos);
  EXPECT_NE(parseError("sphere:1").find("unknown kind 'sphere'"), std::string::npos);
}

TEST(PolynomialSurfaceTerms, InvalidTermsThrow) {
  EXPECT_THROW(PolynomialSurface({{1.0, -1, 0}}), InputError);
  EXPECT_THROW(PolynomialSurface({{std::nan(""), 1, 0}}), InputError);
  EXPECT_THROW(PolynomialSurface::quadratic(INFINITY, 0.0, 0.0), InputError);
}

TEST(PolynomialSurfaceHeightField, SetsZKeepsXY) {
  GeneratorOptions options;
  options.n = 4;
  Mesh mesh = generateMesh(options);
  const Positions flat = mesh.positions;
  const PolynomialSurface surface = PolynomialSurface::parse("polynomial:x^3-3*x*y^2+0.5");
  applyHeightField(surface, mesh.positions);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    EXPECT_EQ(mesh.positions(v, 0), flat(v, 0));
    EXPECT_EQ(mesh.positions(v, 1), flat(v, 1));
    EXPECT_EQ(mesh.positions(v, 2), surface.height(flat(v, 0), flat(v, 1)));
  }
  EXPECT_EQ(mesh.positions(0, 2), -0.125 + 0.375 + 0.5);  // (−1/2, −1/2)
}

}  // namespace
}  // namespace flexure::modeling
