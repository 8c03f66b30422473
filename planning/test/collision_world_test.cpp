// Collision world: mesh loading (STL, OBJ, bad files), FCL objects per group, link updates and
// group distances cross-checked against closed-form distances between primitives.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cobra/planning/collision_world.hpp"
#include "cobra/test_support/test_support.hpp"
#include "planning_fixture.hpp"

// Debian's assimp 5.2.5 leaks two small blocks when it rejects a malformed STL (inside the library,
// after ReadFile returns null); LeakSanitizer is told so, cobra's own leaks stay reported.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so"; }

namespace cobra::planning {
namespace {

using cobra::test_support::messageOf;

TEST(Mesh, AsciiStlAndObjGiveTheSameScaledCube) {
  for (const char* file : {"unit_cube.stl", "unit_cube.obj"}) {
    const TriangleMesh mesh = loadMesh(test::dataDir() / file, 0.1);
    EXPECT_EQ(mesh.triangles.size(), 12u) << file;
    double extent = 0.0;
    for (const auto& v : mesh.vertices)
      for (const double c : v) extent = std::max(extent, std::abs(c));
    EXPECT_NEAR(extent, 0.05, 1e-12) << file;
  }
}

TEST(Mesh, BadFilesNameTheCause) {
  EXPECT_CONTAINS(messageOf([] { loadMesh(test::dataDir() / "none.stl", 1.0); }), "none.stl' not found");
  EXPECT_CONTAINS(messageOf([] { loadMesh(test::dataDir() / "malformed.stl", 1.0); }), "malformed.stl'");
  EXPECT_CONTAINS(messageOf([] { loadMesh(test::dataDir() / "unit_cube.stl", 0.0); }), "scale must be a positive");
}

TEST(CollisionWorld, MalformedMeshNamesObjectLineAndFile) {
  const std::string text = "group g\nobject lump g world mesh malformed.stl at 0 0 0 0 0 0\n";
  const SceneDescription scene = parseScene(text, "bad.scene", test::dataDir());
  const std::string message = messageOf([&] { CollisionWorld world(scene); });
  EXPECT_CONTAINS(message, "bad.scene:2: object 'lump'");
  EXPECT_CONTAINS(message, "malformed.stl' could not be read");
}

/// Two groups, one sphere each, the second attached to a robot's link 0.
SceneDescription twoSpheres(const std::string& second_shape) {
  return parseScene("robot r tools 0 base 0 0 1 0 0 0\ngroup a\ngroup b\n"
                    "object fixed a world sphere 0.1 at 0 0 0 0 0 0\n"
                    "object moving b r.0 " + second_shape + " at 0 0 0 0 0 0\ncheck a b\n",
                    "t.scene", test::dataDir());
}

TEST(CollisionWorld, SphereDistanceFollowsTheLinkInWorldFrame) {
  CollisionWorld world(twoSpheres("sphere 0.05"));
  // Before any update the link sits at the robot base, 1 m above the fixed sphere.
  EXPECT_NEAR(world.distance(0, 1).distance, 1.0 - 0.15, 1e-6);
  const KDL::Frame link(KDL::Vector(0.3, 0.4, 0.0));
  world.setRobotLinks(0, std::span<const KDL::Frame>(&link, 1));
  const GroupDistance d = world.distance(0, 1);
  EXPECT_NEAR(d.distance, 0.5 - 0.15, 1e-6);
  EXPECT_EQ(d.first_object, "fixed");
  EXPECT_EQ(d.second_object, "moving");
  EXPECT_EQ(world.distance(1, 0).first_object, "moving");
  EXPECT_TRUE(KDL::Equal(world.objectPose(1).p, link.p, 1e-12));
}

TEST(CollisionWorld, AnAllowedContactIsLeftOutOfTheDistanceQuery) {
  // Two objects in group b: the probe may touch the phantom (allowed), its holder may not.
  const SceneDescription scene = parseScene(
      "robot r tools 0 base 0 0 1 0 0 0\ngroup a\ngroup b\n"
      "object phantom a world sphere 0.1 at 0 0 0 0 0 0\n"
      "object probe b r.0 sphere 0.05 at 0 0 0 0 0 0\n"
      "object holder b r.0 sphere 0.05 at 0 0 0.3 0 0 0\n"
      "check a b\nallow probe phantom\n",
      "t.scene", test::dataDir());
  ASSERT_EQ(scene.allowed_contacts.size(), 1u);
  CollisionWorld world(scene);
  const KDL::Frame pressing(KDL::Vector(0, 0, 0.14));  // m, world: the probe 0.01 m into the phantom
  world.setRobotLinks(0, std::span<const KDL::Frame>(&pressing, 1));
  const GroupDistance d = world.distance(0, 1);
  EXPECT_NEAR(d.distance, 0.44 - 0.05 - 0.1, 1e-6);  // the holder's distance, not the contact
  EXPECT_EQ(d.second_object, "holder");
}

TEST(CollisionWorld, OverlapReportsZero) {
  CollisionWorld world(twoSpheres("sphere 0.05"));
  const KDL::Frame link(KDL::Vector(0.12, 0, 0));
  world.setRobotLinks(0, std::span<const KDL::Frame>(&link, 1));
  EXPECT_EQ(world.distance(0, 1).distance, 0.0);
}

TEST(CollisionWorld, MeshCubeDistanceMatchesTheBoxPrimitive) {
  // A 0.1 m cube as a mesh and as a box, each probed by a sphere at the same seeded random points.
  for (const std::string shape : {"mesh unit_cube.obj scale 0.1", "box 0.1 0.1 0.1"}) {
    CollisionWorld world(twoSpheres(shape));
    std::uint32_t state = 12345;  // fixed LCG: 50 points, same for both shapes
    for (int i = 0; i < 50; ++i) {
      const auto next = [&] { state = state * 1664525u + 1013904223u; return (state >> 8) / double(1u << 24); };
      const KDL::Vector dir(next() - 0.5, next() - 0.5, next() - 0.5);
      const KDL::Vector centre = dir / dir.Norm() * (0.3 + 0.2 * next());
      const KDL::Frame link(KDL::Rotation::RPY(next(), next(), next()), centre);
      world.setRobotLinks(0, std::span<const KDL::Frame>(&link, 1));
      // Closed form in the cube frame: the fixed sphere's centre (world origin) against the half
      // side 0.05 m, minus the sphere radius 0.1 m.
      const KDL::Vector local = link.M.Inverse() * (KDL::Vector::Zero() - centre);
      double outside = 0.0;
      for (int k = 0; k < 3; ++k) outside += std::pow(std::max(0.0, std::abs(local(k)) - 0.05), 2);
      EXPECT_NEAR(world.distance(0, 1).distance, std::sqrt(outside) - 0.1, 1e-4) << shape << " point " << i;
    }
  }
}

TEST(CollisionWorld, EmptyGroupIsInfinitelyFar) {
  const SceneDescription scene = parseScene("group a\ngroup b\nobject s a world sphere 1 at 0 0 0 0 0 0\n", "e.scene",
                                            test::dataDir());
  CollisionWorld world(scene);
  EXPECT_EQ(world.distance(0, 1).distance, std::numeric_limits<double>::infinity());
  EXPECT_TRUE(world.distance(0, 1).first_object.empty());
}

TEST(CollisionWorld, StopBelowEndsEarlyWithAnUpperBound) {
  const SceneDescription scene = parseScene(
      "group a\ngroup b\nobject s a world sphere 0.1 at 0 0 0 0 0 0\n"
      "object near b world sphere 0.1 at 0.25 0 0 0 0 0\nobject far b world sphere 0.1 at 0 0.5 0 0 0 0\n",
      "e.scene", test::dataDir());
  CollisionWorld world(scene);
  EXPECT_NEAR(world.distance(0, 1).distance, 0.05, 1e-6);
  EXPECT_LE(world.distance(0, 1, 1.0).distance, 1.0);
  EXPECT_NEAR(world.distance(0, 1, 0.06).distance, 0.05, 1e-6);  // under the threshold: that pair
  EXPECT_GT(world.distance(0, 1, 0.04).distance, 0.04);          // none under it: only a bound
}

}  // namespace
}  // namespace cobra::planning
