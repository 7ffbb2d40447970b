// The fields of a viewer page (reports/viewer_fields.h) against known answers: each face's
// smallest angle (per face, at every frame, on the cut faces after a face change), the distance
// to a reference surface (modeling/surface_distance.h: above a face, beyond an edge, beyond a
// corner), the styles by name, and the page's per-face data and its checks.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/surface_distance.h"
#include "render/viewer_page.h"
#include "reports/viewer_fields.h"

namespace flexure {
namespace {

// An equilateral face (60°) and a 30-60-90 one sharing the edge 1–2.
modeling::Mesh twoFaces() {
  modeling::Mesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0, 1, std::sqrt(3.0) / 2, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 1, 3, 2;
  return m;
}

// The unit square [0, 1]² at z = 0 as two faces.
modeling::Mesh unitSquare() {
  modeling::Mesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 2, 3;
  return m;
}

render::ViewerMesh viewerMesh(const modeling::Mesh& mesh) {
  render::ViewerMesh m;
  m.name = "mesh";
  m.triangles = mesh.triangles;
  m.frames = {mesh.positions};
  return m;
}

TEST(SurfaceDistance, KnownAnswersAboveAFaceBeyondAnEdgeAndBeyondACorner) {
  const modeling::SurfaceDistance distance(unitSquare());
  EXPECT_NEAR(distance({0.3, 0.6, 0.25}), 0.25, 1e-15);               // above a face
  EXPECT_NEAR(distance({1.5, 0.5, 0.0}), 0.5, 1e-15);                 // beyond the edge x = 1
  EXPECT_NEAR(distance({-0.3, -0.4, 0.0}), 0.5, 1e-15);               // beyond the corner 0
  EXPECT_NEAR(distance({2.0, 2.0, 1.0}), std::sqrt(3.0), 1e-15);      // beyond the corner 2
  EXPECT_EQ(distance({0.7, 0.2, 0.0}), 0.0);                          // on it
  const modeling::SurfaceDistance half(unitSquare(), {true, false});  // the face 0, 1, 2 alone
  EXPECT_NEAR(half({0.0, 1.0, 0.0}), std::sqrt(0.5), 1e-15);
}

TEST(ViewerFields, SmallestAnglePerFaceAtEveryFrame) {
  const modeling::Mesh mesh = twoFaces();
  render::ViewerPageSpec page;
  page.meshes = {viewerMesh(mesh)};
  modeling::Positions stretched = mesh.positions;
  stretched.col(0) *= 2.0;  // the equilateral face becomes (2, 0), (1, √3/2): atan(√3/2) = 40.9°
  page.meshes[0].frames.push_back(stretched);
  reports::addSmallestAngleFields(page);
  EXPECT_NO_THROW(page.validate());
  EXPECT_TRUE(page.fieldOnFaces);
  EXPECT_EQ(page.style, render::ViewerStyle::Field);
  ASSERT_EQ(page.meshes[0].fields.size(), 2u);
  ASSERT_EQ(page.meshes[0].fields[0].size(), 2);
  EXPECT_NEAR(page.meshes[0].fields[0][0], 60.0, 1e-12);
  EXPECT_NEAR(page.meshes[0].fields[0][1], 30.0, 1e-12);  // (1,0), (1,√3/2), (½,√3/2): 30-60-90
  EXPECT_NEAR(page.meshes[0].fields[1][0], std::atan(std::sqrt(3.0) / 2) * 180 / M_PI, 1e-12);
  const std::string html = render::viewerPageHtml(page);
  EXPECT_NE(html.find("\"fieldOnFaces\":true"), std::string::npos);
  EXPECT_NE(html.find("\"range\":[0,60]"), std::string::npos);
}

TEST(ViewerFields, SmallestAngleFollowsAFaceChange) {
  const modeling::Mesh mesh = twoFaces();
  render::ViewerMesh m = viewerMesh(mesh);
  modeling::Positions grown(5, 3);
  grown << mesh.positions, 0.5, -std::sqrt(3.0) / 2, 0;
  m.frames.push_back(grown);
  modeling::Triangles cut(3, 3);
  cut << 0, 1, 2, 1, 3, 2, 1, 0, 4;  // a third, equilateral face from frame 1 on
  m.faceChanges.push_back({1, cut});
  render::ViewerPageSpec page;
  page.meshes = {m};
  reports::addSmallestAngleFields(page);
  EXPECT_NO_THROW(page.validate());
  EXPECT_EQ(page.meshes[0].fields[0].size(), 2);
  ASSERT_EQ(page.meshes[0].fields[1].size(), 3);
  EXPECT_NEAR(page.meshes[0].fields[1][2], 60.0, 1e-12);
}

TEST(ViewerFields, PerFaceFieldsAreCheckedAgainstTheirFaces) {
  render::ViewerPageSpec page;
  page.meshes = {viewerMesh(twoFaces())};
  page.style = render::ViewerStyle::Field;
  page.fieldOnFaces = true;
  page.meshes[0].fields = {Eigen::VectorXd::Ones(4)};  // a value per vertex, not per face
  EXPECT_THAT([&] { page.validate(); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr(
                  "ViewerPageSpec.meshes[0].fields has 4 values for 2 faces")));
  page.meshes[0].fields = {Eigen::VectorXd::Ones(2)};
  EXPECT_NO_THROW(page.validate());
  page.fieldRange = std::make_pair(1.0, 1.0);
  EXPECT_THAT([&] { page.validate(); }, ::testing::ThrowsMessage<InputError>(
                                            ::testing::HasSubstr("ViewerPageSpec.fieldRange")));
}

// Each vertex of z = x² + y² over [−½, ½]² is z above the plane z = 0, whose square covers
// the feet of the perpendiculars: the error is z.
TEST(ViewerFields, ErrorAgainstAReferenceIsTheDistanceToItsSurface) {
  modeling::GeneratorOptions g;
  g.family = modeling::MeshFamily::Patch48;
  g.n = 8;
  const modeling::Mesh plane = modeling::generateMesh(g);
  modeling::Mesh bowl = plane;
  for (int v = 0; v < bowl.vertexCount(); ++v)
    bowl.positions(v, 2) = bowl.positions.row(v).head<2>().squaredNorm();
  render::ViewerPageSpec page;
  page.meshes = {viewerMesh(bowl)};
  reports::addReferenceDistanceFields(page, plane, "plane.obj");
  EXPECT_NO_THROW(page.validate());
  EXPECT_FALSE(page.fieldOnFaces);
  EXPECT_EQ(page.fieldTitle, "error: distance to plane.obj");
  ASSERT_EQ(page.meshes[0].fields.size(), 1u);
  EXPECT_LE((page.meshes[0].fields[0] - bowl.positions.col(2)).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ViewerFields, StylesByName) {
  EXPECT_EQ(reports::parseViewStyle("isophote").drawing, render::ViewerStyle::Isophote);
  EXPECT_EQ(reports::parseViewStyle("angle").field, reports::ViewerField::Angle);
  EXPECT_EQ(reports::parseViewStyle("error").drawing, render::ViewerStyle::Field);
  EXPECT_EQ(reports::parseViewStyle("reflection").field, reports::ViewerField::None);
  EXPECT_THAT([] { reports::parseViewStyle("field"); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr(
                  "ViewerPageSpec.style 'field': expected reflection | isophote")));
}

}  // namespace
}  // namespace flexure
