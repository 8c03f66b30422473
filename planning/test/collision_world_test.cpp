// Collision world: mesh loading (STL, OBJ, bad files), FCL objects per group, link updates and
// group distances cross-checked against closed-form distances between primitives.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

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

// distanceUnder is the exact minimum over the groups' pairs whenever it is under the bound: 300
// seeded random placements of a robot's box, cylinder and sphere among a fixed box, capsule and
// sphere, each queried unbounded and with bounds just above and just below the minimum of the
// pairs' own distances (objectDistance, one narrow phase per pair: an independent minimum). A
// pair skipped although closer than the bound (a stale memo, say) would return the bound instead.
TEST(CollisionWorld, DistanceUnderABoundIsTheExactMinimumOfItsPairs) {
  const SceneDescription scene = parseScene(
      "robot r tools 0 base 0 0 0 0 0 0\ngroup a\ngroup b\n"
      "object brick a r.0 box 0.08 0.05 0.03 at 0 0 0 0 0 0\n"
      "object rod a r.1 cylinder 0.02 0.2 at 0 0 0 0 0 0\n"
      "object ball a r.2 sphere 0.04 at 0 0 0 0 0 0\n"
      "object table b world box 0.4 0.4 0.02 at 0 0 -0.2 0 0 0\n"
      "object post b world capsule 0.03 0.3 at 0.2 0.1 0 0 0 0\n"
      "object knob b world sphere 0.05 at -0.15 -0.1 0.05 0 0 0\ncheck a b\n",
      "u.scene", test::dataDir());
  CollisionWorld world(scene);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> position(-0.25, 0.25), angle(-3.1, 3.1), margin(0.0, 0.03);
  const std::size_t robot_objects[] = {0, 1, 2}, fixed_objects[] = {3, 4, 5};
  int bounded_hits = 0;
  for (int n = 0; n < 300; ++n) {
    std::array<KDL::Frame, 3> links{};
    for (KDL::Frame& link : links)
      link = KDL::Frame(KDL::Rotation::RPY(angle(rng), angle(rng), angle(rng)),
                        KDL::Vector(position(rng), position(rng), position(rng)));
    world.setRobotLinks(0, links);
    double minimum = std::numeric_limits<double>::infinity();
    for (const std::size_t i : robot_objects)
      for (const std::size_t j : fixed_objects) minimum = std::min(minimum, world.objectDistance(i, j));
    EXPECT_NEAR(world.distanceUnder(0, 1, std::numeric_limits<double>::infinity()).distance, minimum, 1e-9)
        << "placement " << n;
    if (minimum == 0.0) continue;  // overlapping: no bound under it
    const double above = minimum + margin(rng);
    const GroupDistance under = world.distanceUnder(0, 1, above);
    if (above > minimum + 1e-6) {
      EXPECT_NEAR(under.distance, minimum, 1e-9) << "placement " << n << ", bound " << above;
      EXPECT_FALSE(under.first_object.empty()) << "placement " << n;
      ++bounded_hits;
    }
    const GroupDistance below = world.distanceUnder(0, 1, 0.999 * minimum);
    EXPECT_EQ(below.distance, 0.999 * minimum) << "placement " << n;
    EXPECT_TRUE(below.first_object.empty()) << "placement " << n;
  }
  EXPECT_GT(bounded_hits, 100);  // about half the placements overlap
}

// The pair memos answer while neither object moved and are measured again when one did: over
// seeded random sequences (seed 23) in which each step moves one link, all, or none (the same
// frames set again), every pair's distance and the group minimum equal those of a world that
// measures the same placement afresh (bitwise: the same narrow phase on the same transforms).
TEST(CollisionWorld, MemoisedDistancesEqualFreshOnesWhateverMoved) {
  const std::string text =
      "robot r tools 0 base 0 0 0 0 0 0\ngroup a\ngroup b\n"
      "object brick a r.0 box 0.08 0.05 0.03 at 0 0 0 0 0 0\n"
      "object rod a r.1 cylinder 0.02 0.2 at 0 0 0 0 0 0\n"
      "object ball a r.2 sphere 0.04 at 0 0 0 0 0 0\n"
      "object table b world box 0.4 0.4 0.02 at 0 0 -0.2 0 0 0\n"
      "object post b world capsule 0.03 0.3 at 0.2 0.1 0 0 0 0\ncheck a b\n";
  const SceneDescription scene = parseScene(text, "m.scene", test::dataDir());
  CollisionWorld world(scene);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> position(-0.25, 0.25), angle(-3.1, 3.1);
  std::uniform_int_distribution<int> which(0, 4);  // 0-2: that link, 3: all, 4: none
  std::array<KDL::Frame, 3> links{};
  const auto random = [&] {
    return KDL::Frame(KDL::Rotation::RPY(angle(rng), angle(rng), angle(rng)),
                      KDL::Vector(position(rng), position(rng), position(rng)));
  };
  for (KDL::Frame& link : links) link = random();
  for (int n = 0; n < 200; ++n) {
    const int move = which(rng);
    for (int i = 0; i < 3; ++i)
      if (move == i || move == 3) links[static_cast<std::size_t>(i)] = random();
    world.setRobotLinks(0, links);
    CollisionWorld fresh(scene);
    fresh.setRobotLinks(0, links);
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 3; j < 5; ++j)
        EXPECT_EQ(world.objectDistance(i, j), fresh.objectDistance(i, j)) << "step " << n << ", pair " << i << "-" << j;
    CollisionWorld fresh_group(scene);
    fresh_group.setRobotLinks(0, links);
    EXPECT_EQ(world.distanceUnder(0, 1, std::numeric_limits<double>::infinity()).distance,
              fresh_group.distanceUnder(0, 1, std::numeric_limits<double>::infinity()).distance)
        << "step " << n;
  }
}

}  // namespace
}  // namespace cobra::planning
