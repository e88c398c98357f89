// The object's distance field against exact distances: analytic ones on a box, the mesh's own
// (CGAL closest points and inside test) on a sphere; its exact near-surface queries against
// brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/mesh_query.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/simulation/distance_field.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

// Signed distance from p to the surface of the box [-half, half] centred at the origin.
double boxSignedDistance(const Eigen::Vector3d& half, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = p.cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

TEST(DistanceField, BoxValuesWithinTheBoundAndLowerBoundsHold) {
  const Eigen::Vector3d size(0.06, 0.04, 0.1), half = size / 2;
  const TriangleMesh mesh = geometry::shapes::makeBox(size);
  DistanceFieldParams params;
  params.band_m = 0.008;
  const DistanceField field(mesh, true, params);
  EXPECT_TRUE(field.isSigned());
  EXPECT_DOUBLE_EQ(field.spacing(), params.spacing_m);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-0.08, 0.08);
  int in_band = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    const double exact = boxSignedDistance(half, p);
    const double bound = field.lowerBound(p);
    ASSERT_LE(bound, exact + 1e-12) << p.transpose();
    // Every corner of p's cell lies within the band: exact values.
    if (std::abs(exact) < params.band_m - std::sqrt(3.0) * field.spacing()) {
      ++in_band;
      // Near the surface the field holds exact values: interpolation and bound are tight.
      EXPECT_NEAR(field.value(p), exact, field.errorBound()) << p.transpose();
      EXPECT_GE(bound, exact - 2 * field.errorBound()) << p.transpose();
    }
    if (exact > params.band_m + 2 * field.spacing()) {
      EXPECT_GT(field.value(p), 0);
    }
    if (exact < -params.band_m - 2 * field.spacing()) {
      EXPECT_LT(field.value(p), 0);
    }
  }
  EXPECT_GT(in_band, 500);
  EXPECT_LT(field.value(Eigen::Vector3d::Zero()), 0);  // inside
  // 2 cm outside in x: beyond the band the field holds the band's width.
  EXPECT_NEAR(field.value(Eigen::Vector3d(0.05, 0, 0)), params.band_m, 1e-6);
  EXPECT_NEAR(field.value(Eigen::Vector3d(0.031, 0, 0)), 0.001, 1e-6);  // planar: exact
  // Far from the grid the bound is the distance to the box.
  EXPECT_NEAR(field.lowerBound(Eigen::Vector3d(1.03, 0, 0)), 1.0, 1e-12);
}

TEST(DistanceField, SphereMeshAgreesWithExactMeshDistanceAndInsideTest) {
  const TriangleMesh mesh = geometry::shapes::makeSphere(0.04, 48, 24);
  const GraspObject object(mesh);
  ASSERT_TRUE(object.closed());
  const DistanceField& field = object.distanceField();
  ASSERT_TRUE(field.isSigned());
  const auto& query = object.surfaceQuery();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-0.06, 0.06);
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    const double unsigned_distance = query.distance(p);
    const double exact = query.contains(p) ? -unsigned_distance : unsigned_distance;
    ASSERT_LE(field.lowerBound(p), exact + 1e-12) << p.transpose();
    if (unsigned_distance < 0.002) {
      EXPECT_NEAR(field.value(p), exact, field.errorBound()) << p.transpose();
      // The exact near-surface query finds the same closest point.
      const auto closest = field.closestPointWithin(p, 0.003);
      ASSERT_TRUE(closest.has_value());
      EXPECT_NEAR(closest->distance, unsigned_distance, 1e-9);
      EXPECT_LT((closest->point - query.closestPoint(p)).norm(), 1e-6);
    }
    if (unsigned_distance > 0.0035) {
      EXPECT_FALSE(field.closestPointWithin(p, 0.003).has_value());
    }
    if (std::abs(exact) > 0.01) {
      EXPECT_EQ(field.value(p) < 0, exact < 0) << p.transpose();
    }
  }
}

TEST(DistanceField, BoxDistanceIsTheExactGapOfASolidBox) {
  const TriangleMesh mesh = geometry::shapes::makeSphere(0.04, 48, 24);
  const geometry::MeshQuery query(mesh);
  const DistanceField field(mesh, true);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  int near = 0;
  for (int i = 0; i < 120; ++i) {
    const Eigen::Vector3d half(0.004 + 0.01 * std::abs(unit(rng)),
                               0.004 + 0.01 * std::abs(unit(rng)), 0.02);
    Pose pose = Pose::Identity();
    pose.linear() = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng))
                        .normalized()
                        .toRotationMatrix();
    const Eigen::Vector3d direction = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    pose.translation() = direction * (0.04 + half.minCoeff() + 0.006 * unit(rng));
    // Brute force: the distance of a dense grid of points on the box's faces bounds the gap
    // from above, and from below up to half the grid's diagonal.
    constexpr int kSteps = 24;
    double sampled = std::numeric_limits<double>::infinity();
    double cell = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      cell = std::max(cell, std::hypot(2 * half[u], 2 * half[v]) / kSteps);
      for (int side : {-1, 1}) {
        for (int a = 0; a <= kSteps; ++a) {
          for (int b = 0; b <= kSteps; ++b) {
            Eigen::Vector3d local;
            local[axis] = side * half[axis];
            local[u] = half[u] * (2.0 * a / kSteps - 1);
            local[v] = half[v] * (2.0 * b / kSteps - 1);
            const Eigen::Vector3d p = pose * local;
            sampled = std::min(sampled, query.contains(p) ? 0.0 : query.distance(p));
          }
        }
      }
    }
    const double upper = 0.02;
    const double gap = field.boxDistance(pose, half, upper);
    if (sampled >= upper + cell) {
      EXPECT_DOUBLE_EQ(gap, upper);
      continue;
    }
    ++near;
    EXPECT_LE(gap, sampled + 1e-9) << i;
    // A box intersecting the surface has gap 0, and then some sample is inside or on it.
    EXPECT_GE(gap, sampled - cell / 2 - 1e-9) << i;
    EXPECT_LE(field.lowerBound(pose.translation()) - half.norm(), gap + 1e-9) << i;
  }
  EXPECT_GT(near, 40);
}

// A finger pad over a flat face: hundreds of coplanar triangles lie at nearly the same distance,
// the case where the query cuts triangles by separating axes instead of testing each exactly.
// The gap of a box above a large flat face is the height of its lowest corner, and the closest
// points are that corner and the point of the face below it.
TEST(DistanceField, BoxDistanceOverAFlatFaceIsItsLowestCornersHeight) {
  const Eigen::Vector3d object_half(0.06, 0.06, 0.03);
  const TriangleMesh mesh = geometry::shapes::makeBox(2 * object_half, 40);
  const DistanceField field(mesh, true);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d half(0.008, 0.01, 0.004 + 0.01 * std::abs(unit(rng)));
    Pose pose = Pose::Identity();
    // Tilts up to about 6 degrees, any turn about the face's normal.
    pose.linear() = (Eigen::AngleAxisd(M_PI * unit(rng), Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(0.1 * unit(rng), Eigen::Vector3d::UnitX()) *
                     Eigen::AngleAxisd(0.1 * unit(rng), Eigen::Vector3d::UnitY()))
                        .toRotationMatrix();
    double lowest = std::numeric_limits<double>::infinity();
    Eigen::Vector3d lowest_corner = Eigen::Vector3d::Zero();
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner((c & 1) ? half.x() : -half.x(), (c & 2) ? half.y() : -half.y(),
                                   (c & 4) ? half.z() : -half.z());
      if ((pose.linear() * corner).z() < lowest) {
        lowest = (pose.linear() * corner).z();
        lowest_corner = corner;
      }
    }
    const double height = 0.004 * std::abs(unit(rng));  // of the lowest corner above the face
    pose.translation() =
        Eigen::Vector3d(0.02 * unit(rng), 0.02 * unit(rng), object_half.z() + height - lowest);
    EXPECT_NEAR(field.boxDistance(pose, half, 0.01), height, 1e-9) << i;
    // Tilted, the box touches with its lowest corner: the closest points, from the face the
    // gap was found at, are that corner and the point of the face below it.
    const DistanceField::BoxGap gap = field.boxGapAndFace(pose, half, 0.01);
    EXPECT_EQ(gap.distance, field.boxDistance(pose, half, 0.01)) << i;
    if (height < 1e-6) continue;  // touching: no unique pair
    ASSERT_TRUE(gap.face.has_value()) << i;
    const auto pair = field.boxClosestPointsOnFace(pose, half, *gap.face);
    ASSERT_TRUE(pair.has_value()) << i;
    const Eigen::Vector3d corner = pose * lowest_corner;
    EXPECT_NEAR(pair->on_surface.distance, height, 1e-9) << i;
    EXPECT_LT((pair->on_box - corner).norm(), 1e-6) << i;
    EXPECT_LT(
        (pair->on_surface.point - Eigen::Vector3d(corner.x(), corner.y(), object_half.z())).norm(),
        1e-6)
        << i;
  }
  EXPECT_THROW(
      field.boxClosestPointsOnFace(Pose::Identity(), Eigen::Vector3d::Constant(0.01), 1u << 30),
      InvalidArgument);
  // Farther than `upper`: the gap comes back as `upper`, with no face.
  Pose far = Pose::Identity();
  far.translation() = Eigen::Vector3d(0, 0, object_half.z() + 0.05);
  const DistanceField::BoxGap far_gap =
      field.boxGapAndFace(far, Eigen::Vector3d::Constant(0.01), 0.01);
  EXPECT_EQ(far_gap.distance, 0.01);
  EXPECT_FALSE(far_gap.face.has_value());
}

// Boxes of finger-pad size about a mesh's surface, from just inside to 15 mm out, turned at random.
std::vector<std::pair<Pose, Eigen::Vector3d>> boxesNearSurface(const TriangleMesh& mesh, int count,
                                                               std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<std::size_t> face(0, mesh.faces.size() - 1);
  std::vector<std::pair<Pose, Eigen::Vector3d>> boxes;
  for (int i = 0; i < count; ++i) {
    const auto& t = mesh.faces[face(rng)];
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]],
                          &c = mesh.vertices[t[2]];
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    const Eigen::Vector3d half(0.003 + 0.012 * std::abs(unit(rng)),
                               0.003 + 0.012 * std::abs(unit(rng)),
                               0.002 + 0.01 * std::abs(unit(rng)));
    Pose pose = Pose::Identity();
    pose.linear() = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng))
                        .normalized()
                        .toRotationMatrix();
    const double offset = half.minCoeff() + 0.0075 + 0.0085 * unit(rng);  // -1 mm ... 16 mm
    pose.translation() = (a + b + c) / 3 + normal * offset;
    boxes.emplace_back(pose, half);
  }
  return boxes;
}

// A sphere, a box and a torus, and those of the named YCB meshes the shared data holds (thin,
// hollow, with many small triangles); without the shared data, the generated ones only.
std::vector<std::pair<std::string, TriangleMesh>> generatedAndYcbMeshes(
    const std::vector<std::string>& ycb_names) {
  std::vector<std::pair<std::string, TriangleMesh>> meshes = {
      {"sphere", geometry::shapes::makeSphere(0.04, 48, 24)},
      {"box", geometry::shapes::makeBox({0.06, 0.2, 0.04}, 4)},
      {"torus", geometry::shapes::makeTorus(0.05, 0.015)}};
  const std::string shared = test::sharedDataDir();
  if (shared.empty()) {
    std::printf("shared data not found: real meshes skipped, generated ones compared\n");
    return meshes;
  }
  for (const auto& name : ycb_names) {
    const std::string path = shared + "/objects/ycb/" + name + ".ply";
    if (std::filesystem::exists(path)) meshes.emplace_back(name, loadMesh(path));
  }
  return meshes;
}

// Skipping empty cells 64 at a time changes which cells are stepped over, never which are visited
// or in what order: the same gap and the same closest face for every box, on generated meshes and
// on real ones (thin, hollow, with many small triangles).
TEST(DistanceField, SkippingEmptyCellsGivesTheSameGapsAndFaces) {
  const auto meshes = generatedAndYcbMeshes({"011_banana", "025_mug", "048_hammer"});
  DistanceFieldParams dense;
  dense.skip_empty_cells = false;
  constexpr double kUpper = 0.01;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const auto& [name, mesh] = meshes[m];
    const DistanceField skipping(mesh, true), stepping(mesh, true, dense);
    int near = 0, touching = 0;
    for (const auto& [pose, half] : boxesNearSurface(mesh, 1500, 40 + m)) {
      const DistanceField::BoxGap a = skipping.boxGapAndFace(pose, half, kUpper);
      const DistanceField::BoxGap b = stepping.boxGapAndFace(pose, half, kUpper);
      ASSERT_EQ(a.distance, b.distance) << name;
      ASSERT_EQ(a.face, b.face) << name;
      near += a.distance < kUpper;
      touching += a.distance == 0;
    }
    // Both kinds of answer occur: exact gaps below the bound, and boxes touching the surface.
    EXPECT_GT(near, 500) << name;
    EXPECT_GT(touching, 50) << name;
  }
}

// A hint only bounds the search: whatever face it names (the closest one, the last box's, any
// other, one out of range), the gap and the face are those of the search without a hint, on
// generated and real meshes.
TEST(DistanceField, AGapHintNeverChangesTheGapOrTheFace) {
  const auto meshes = generatedAndYcbMeshes({"011_banana", "025_mug", "073-a_lego_duplo"});
  constexpr double kUpper = 0.01;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const auto& [name, mesh] = meshes[m];
    const DistanceField field(mesh, true);
    std::mt19937_64 rng(90 + m);
    std::uniform_int_distribution<std::size_t> any_face(0, mesh.faces.size() - 1);
    std::optional<std::size_t> last_face;
    int near = 0, touching = 0;
    for (const auto& [pose, half] : boxesNearSurface(mesh, 800, 60 + m)) {
      const DistanceField::BoxGap plain = field.boxGapAndFace(pose, half, kUpper);
      std::vector<std::size_t> hints = {any_face(rng), mesh.faces.size() + 3};
      if (plain.face) hints.push_back(*plain.face);
      if (last_face) hints.push_back(*last_face);
      for (std::size_t hint : hints) {
        const DistanceField::BoxGap hinted = field.boxGapAndFace(pose, half, kUpper, hint);
        ASSERT_EQ(hinted.distance, plain.distance) << name << " hint " << hint;
        ASSERT_EQ(hinted.face.has_value(), plain.face.has_value()) << name;
        // Touching: any face the box touches (the search stops at the first).
        if (plain.distance > 0) {
          ASSERT_EQ(hinted.face, plain.face) << name << " hint " << hint;
        } else {
          ASSERT_FALSE(field.boxClosestPointsOnFace(pose, half, *hinted.face)) << name;
        }
      }
      if (plain.face) last_face = plain.face;
      near += plain.distance < kUpper;
      touching += plain.distance == 0;
    }
    EXPECT_GT(near, 250) << name;
    EXPECT_GT(touching, 25) << name;
  }
}

// The box intersection test says what the exact gap says: a face comes back exactly when the gap
// is 0, whatever face the hint names, and the box touches that face; on generated and real meshes.
// Boxes wholly inside a closed surface meet no face.
TEST(DistanceField, BoxIntersectionIsAZeroGapWhateverTheHint) {
  const auto meshes = generatedAndYcbMeshes({"011_banana", "025_mug", "073-a_lego_duplo"});
  constexpr double kUpper = 0.01;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const auto& [name, mesh] = meshes[m];
    const DistanceField field(mesh, true);
    std::mt19937_64 rng(120 + m);
    std::uniform_int_distribution<std::size_t> any_face(0, mesh.faces.size() - 1);
    std::optional<std::size_t> last_face;
    int hits = 0, misses = 0;
    for (const auto& [pose, half] : boxesNearSurface(mesh, 1500, 140 + m)) {
      const bool touching = field.boxDistance(pose, half, kUpper) == 0;
      const std::optional<std::size_t> plain = field.boxIntersection(pose, half);
      ASSERT_EQ(plain.has_value(), touching) << name;
      std::vector<std::optional<std::size_t>> hints = {any_face(rng), mesh.faces.size() + 3};
      if (last_face) hints.push_back(last_face);
      for (const auto& hint : hints) {
        const std::optional<std::size_t> hinted = field.boxIntersection(pose, half, hint);
        ASSERT_EQ(hinted.has_value(), touching) << name;
        if (hinted) {
          ASSERT_FALSE(field.boxClosestPointsOnFace(pose, half, *hinted)) << name;
        }
      }
      if (plain) last_face = plain;
      hits += touching;
      misses += !touching;
    }
    EXPECT_GT(hits, 100) << name;
    EXPECT_GT(misses, 100) << name;
  }
  const Eigen::Vector3d object_half(0.05, 0.05, 0.05);
  const DistanceField box_field(geometry::shapes::makeBox(2 * object_half, 4), true);
  Pose inside = Pose::Identity();
  inside.linear() =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_FALSE(box_field.boxIntersection(inside, Eigen::Vector3d(0.02, 0.01, 0.03)));
  inside.translation().x() = object_half.x();  // straddling a face now
  EXPECT_TRUE(box_field.boxIntersection(inside, Eigen::Vector3d(0.02, 0.01, 0.03)));
}

// Boxes level over a flat face of many triangles are equally far from every triangle below them:
// the face returned is the same whichever of those triangles the hint names (the least index of
// the closest ones), not the one the search happened to meet first.
TEST(DistanceField, OfEquallyCloseFacesTheSameOneWhateverTheHint) {
  const Eigen::Vector3d object_half(0.06, 0.06, 0.03);
  const TriangleMesh mesh = geometry::shapes::makeBox(2 * object_half, 40);
  const DistanceField field(mesh, true);
  const Eigen::Vector3d half(0.008, 0.01, 0.005);
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(-1, 1);
  int ties = 0;
  for (int i = 0; i < 40; ++i) {
    Pose pose = Pose::Identity();
    const double height = 0.001 + 0.004 * std::abs(unit(rng));
    pose.translation() =
        Eigen::Vector3d(0.02 * unit(rng), 0.02 * unit(rng), object_half.z() + half.z() + height);
    const DistanceField::BoxGap plain = field.boxGapAndFace(pose, half, 0.01);
    ASSERT_TRUE(plain.face.has_value()) << i;
    EXPECT_NEAR(plain.distance, height, 1e-12) << i;
    std::vector<std::size_t> closest;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto pair = field.boxClosestPointsOnFace(pose, half, f);
      if (pair && std::abs(pair->on_surface.distance - plain.distance) < 1e-12)
        closest.push_back(f);
    }
    ties += closest.size() > 1;
    for (std::size_t hint : closest) {
      EXPECT_EQ(field.boxGapAndFace(pose, half, 0.01, hint).face, plain.face) << i << " " << hint;
    }
  }
  EXPECT_EQ(ties, 40);
}

TEST(DistanceField, GraspObjectRejectsBadFieldParamsWhenConstructed) {
  DistanceFieldParams params;
  params.band_m = -0.001;
  EXPECT_THROW(GraspObject(geometry::shapes::makeBox({0.05, 0.05, 0.05}), params), InvalidArgument);
}

TEST(DistanceField, MemoryGuardGrowsTheSpacingAndOpenMeshesAreUnsigned) {
  TriangleMesh open = geometry::shapes::makeBox({0.1, 0.1, 0.1});
  open.faces.pop_back();
  open.faces.pop_back();
  DistanceFieldParams params;
  params.max_nodes = 20000;
  const DistanceField field(open, false, params);
  EXPECT_FALSE(field.isSigned());
  EXPECT_LE(field.nodeCount(), params.max_nodes);
  EXPECT_GT(field.spacing(), params.spacing_m);
  EXPECT_GE(field.value(Eigen::Vector3d::Zero()), 0);
  EXPECT_LE(field.lowerBound(Eigen::Vector3d(0.07, 0, 0)), 0.02 + 1e-12);
  params.spacing_m = 0;
  EXPECT_THROW(DistanceField(open, false, params), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::grasping
