#include "skelgrasp/geometry/shapes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/mesh_topology.h"

namespace skelgrasp {
namespace {

TEST(Primitives, SingleShapesAreClosedOutwardAndHaveTheRightVolume) {
  struct Case {
    const char* name;
    TriangleMesh mesh;
    double volume;
    double tolerance;
  };
  const std::vector<Case> cases = {
      {"box", geometry::shapes::makeBox({0.1, 0.2, 0.3}, 3), 0.006, 1e-12},
      {"sphere", geometry::shapes::makeSphere(0.05, 64, 32), 4.0 / 3 * kPi * std::pow(0.05, 3),
       0.01},
      {"cylinder", geometry::shapes::makeCylinder(0.02, 0.1, 64), kPi * 0.0004 * 0.1, 0.01},
      {"capsule", geometry::shapes::makeCapsule(0.02, 0.1, 64),
       kPi * 0.0004 * 0.1 + 4.0 / 3 * kPi * std::pow(0.02, 3), 0.01},
      {"torus", geometry::shapes::makeTorus(0.06, 0.01, 96, 32), 2 * kPi * kPi * 0.06 * 0.0001,
       0.01},
  };
  for (const auto& c : cases) {
    const auto t = geometry::analyzeTopology(c.mesh);
    EXPECT_TRUE(t.closed) << c.name;
    EXPECT_EQ(t.inconsistently_oriented_edges, 0u) << c.name;
    EXPECT_EQ(t.components, 1u) << c.name;
    EXPECT_NEAR(c.mesh.signedVolume(), c.volume, c.volume * c.tolerance + 1e-15) << c.name;
  }
}

TEST(Primitives, NamedShapesAreClosedPartsOfPlausibleSize) {
  for (const auto& name : geometry::shapes::namedShapes()) {
    const TriangleMesh mesh = geometry::shapes::makeNamedShape(name);
    const auto t = geometry::analyzeTopology(mesh);
    EXPECT_TRUE(t.closed) << name;  // each part closed; parts may overlap
    EXPECT_GT(t.signed_volume, 0) << name;
    const double size = mesh.bounds().extent().maxCoeff();
    EXPECT_GT(size, 0.04) << name;
    EXPECT_LT(size, 0.4) << name;
  }
  EXPECT_THROW(geometry::shapes::makeNamedShape("teapot"), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp
