// Scene files: the documented line format, its errors (file:line and what to do), validation.

#include <gtest/gtest.h>

#include <cmath>

#include "cobra/planning/collision_world.hpp"
#include "cobra/planning/scene.hpp"
#include "cobra/test_support/test_support.hpp"
#include "planning_fixture.hpp"

namespace cobra::planning {
namespace {

using cobra::test_support::messageOf;

SceneDescription parse(const std::string& text) { return parseScene(text, "s.scene", test::dataDir()); }

TEST(Scene, ParsesTheTestSceneFile) {
  const SceneDescription scene = loadScene(test::dataDir() / "two_robots.scene");
  EXPECT_DOUBLE_EQ(scene.min_collision_distance, 0.005);
  ASSERT_EQ(scene.robots.size(), 2u);
  EXPECT_EQ(scene.robots[1].name, "ur5");
  EXPECT_EQ(scene.robots[1].tool_indices, std::vector<std::size_t>{1});
  EXPECT_EQ(scene.groups, (std::vector<std::string>{"macro", "micro", "ur5", "environment"}));
  ASSERT_EQ(scene.objects.size(), 6u);
  const ObjectDescription& needle = scene.objects[2];
  EXPECT_EQ(needle.group, "micro");
  EXPECT_EQ(needle.attached_to.robot_name, "isur");
  EXPECT_EQ(needle.attached_to.link_index, 1u);
  EXPECT_EQ(needle.shape.kind, ShapeKind::Cylinder);
  EXPECT_DOUBLE_EQ(needle.shape.dimensions[0], 0.002);
  EXPECT_DOUBLE_EQ(needle.offset.p.z(), -0.05);
  EXPECT_CONTAINS(needle.origin, "two_robots.scene:13");
  const ObjectDescription& phantom = scene.objects[5];
  EXPECT_TRUE(phantom.attached_to.isWorld());
  EXPECT_EQ(phantom.shape.mesh_path, test::dataDir() / "unit_cube.stl");
  EXPECT_DOUBLE_EQ(phantom.shape.mesh_scale, 0.1);
  ASSERT_EQ(scene.checks.size(), 5u);
  EXPECT_EQ(scene.checks[3].first, scene.groupIndex("micro"));
  EXPECT_EQ(scene.checks[3].second, scene.groupIndex("environment"));
}

TEST(Scene, PoseIsXyzThenRollPitchYaw) {
  const SceneDescription scene = parse("robot r tools 0 1 base 1 2 3 0.1 0.2 0.3\n");
  const KDL::Frame expected(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(1, 2, 3));
  EXPECT_TRUE(KDL::Equal(scene.robots[0].base_in_world, expected, 1e-12));
  EXPECT_EQ(scene.robots[0].tool_indices, (std::vector<std::size_t>{0, 1}));
}

TEST(Scene, RobotsMayNameTheirToolFrame) {
  const SceneDescription scene = parse("robot r tools 0 base 0 0 1 0 0 0 tool 0 0 0.1 0 1.5708 0\n");
  EXPECT_TRUE(KDL::Equal(scene.robots[0].toolFrame(0),
                         KDL::Frame(KDL::Rotation::RPY(0, 1.5708, 0), KDL::Vector(0, 0, 0.1)), 1e-12));
  EXPECT_TRUE(KDL::Equal(parse("robot r tools 0 base 0 0 1 0 0 0\n").robots[0].toolFrame(0), KDL::Frame::Identity(),
                         1e-15));
}

TEST(Scene, EachToolOfATwoToolRobotHasItsOwnFrame) {
  // The robot line's `tool` gives every tool's frame; a `tool` statement one tool's (its index
  // among the robot's tools, not the pose of q it takes: `tools 1 0` makes tool 0 the second pose).
  const SceneDescription scene = parse(
      "robot r tools 1 0 base 0 0 1 0 0 0 tool 0 0 0 0 1.5708 0\n"
      "tool r 1 at 0 0 0.15 0 -0.6 0\n");
  const RobotPlacement& robot = scene.robots[0];
  ASSERT_EQ(robot.tool_frames.size(), 2u);
  EXPECT_TRUE(KDL::Equal(robot.toolFrame(0), KDL::Frame(KDL::Rotation::RPY(0, 1.5708, 0)), 1e-12));
  EXPECT_TRUE(KDL::Equal(robot.toolFrame(1), KDL::Frame(KDL::Rotation::RPY(0, -0.6, 0), KDL::Vector(0, 0, 0.15)), 1e-12));
  // Without the robot line's `tool`, the tools a statement does not name stay identity.
  const SceneDescription one = parse("robot r tools 0 1 base 0 0 1 0 0 0\ntool r 1 at 0 0 0.15 0 0 0\n");
  EXPECT_TRUE(KDL::Equal(one.robots[0].toolFrame(0), KDL::Frame::Identity(), 1e-15));
  EXPECT_TRUE(KDL::Equal(one.robots[0].toolFrame(1), KDL::Frame(KDL::Vector(0, 0, 0.15)), 1e-15));
}

TEST(Scene, AToolTheRobotDoesNotHaveIsNamedWithTheRobotsToolCount) {
  EXPECT_CONTAINS(messageOf([] { parse("robot r tools 0 1 base 0 0 1 0 0 0\n\ntool r 2 at 0 0 0 0 0 0\n"); }),
                  "s.scene:3: robot 'r' has 2 tools (`tools 0 1`): no tool 2 (a tool index counts the robot's "
                  "tools from 0, in the order of its `tools`)");
  EXPECT_CONTAINS(messageOf([] { parse("robot ur5 tools 1 base 0 0 1 0 0 0\ntool ur5 1 at 0 0 0 0 0 0\n"); }),
                  "s.scene:2: robot 'ur5' has 1 tool (`tools 1`): no tool 1");
  EXPECT_CONTAINS(messageOf([] { parse("tool r 0 at 0 0 0 0 0 0\n"); }),
                  "s.scene:1: unknown robot 'r' (declare it with `robot` first)");
  EXPECT_CONTAINS(messageOf([] { parse("robot r tools 0 base 0 0 1 0 0 0\ntool r 0 at 0 0 0 0 0 0\n"
                                       "tool r 0 at 0 0 0.1 0 0 0\n"); }),
                  "s.scene:3: tool 0 of robot 'r' given twice");
  EXPECT_CONTAINS(messageOf([] { parse("robot r tools 0 base 0 0 1 0 0 0\ntool r 0 0 0 0 0 0 0\n"); }),
                  "s.scene:2: expected 'at', found '0'");
}

TEST(Scene, ValidateWantsOneToolFramePerTool) {
  SceneDescription scene;
  RobotPlacement robot;
  robot.name = "isur";
  robot.tool_indices = {0, 1};
  robot.tool_frames = {KDL::Frame::Identity()};
  scene.robots.push_back(robot);
  EXPECT_CONTAINS(messageOf([&] { scene.validate(); }),
                  "scene: robot 'isur' has 2 tool(s) but 1 tool frames: give one per tool (or none: identity)");
  scene.robots[0].tool_frames.clear();
  EXPECT_NO_THROW(scene.validate());
}

TEST(Scene, CommentsAndBlankLinesAreIgnored) {
  const SceneDescription scene = parse("# a comment\n\n  group g   # trailing comment\r\n");
  EXPECT_EQ(scene.groups, std::vector<std::string>{"g"});
}

TEST(Scene, ErrorsNameFileLineAndCause) {
  EXPECT_CONTAINS(messageOf([] { parse("group g\nfly away\n"); }), "s.scene:2: unknown statement 'fly'");
  EXPECT_CONTAINS(messageOf([] { parse("min_collision_distance abc\n"); }), "s.scene:1: expected a distance [m]");
  EXPECT_CONTAINS(messageOf([] { parse("min_collision_distance nan\n"); }), "s.scene:1:");
  EXPECT_CONTAINS(messageOf([] { parse("object o nowhere world sphere 1 at 0 0 0 0 0 0\n"); }),
                  "s.scene:1: unknown group 'nowhere' (declare it with `group` first)");
  EXPECT_CONTAINS(messageOf([] { parse("group g\nobject o g arm.1 sphere 1 at 0 0 0 0 0 0\n"); }),
                  "s.scene:2: unknown robot 'arm'");
  EXPECT_CONTAINS(messageOf([] { parse("group g\nobject o g world sphere -1 at 0 0 0 0 0 0\n"); }),
                  "s.scene:2: object 'o': sphere dimensions must be > 0 m");
  EXPECT_CONTAINS(messageOf([] { parse("group g\nobject o g world cone 1 at 0 0 0 0 0 0\n"); }),
                  "s.scene:2: unknown shape 'cone'");
  EXPECT_CONTAINS(messageOf([] { parse("group g\nobject o g world sphere 1 at 0 0 0 0 0\n"); }),
                  "s.scene:2: expected yaw [rad] at the end of the line");
  EXPECT_CONTAINS(messageOf([] { parse("group g\ngroup g\n"); }), "s.scene:2: group 'g' declared twice");
  EXPECT_CONTAINS(messageOf([] { parse("group g\ncheck g g\n"); }), "s.scene:2: a check needs two different groups");
  EXPECT_CONTAINS(messageOf([] { parse("group g\nobject o g world sphere 1 at 0 0 0 0 0 0\nallow o x\n"); }),
                  "s.scene:3: unknown object 'x' (declare it with `object` first)");
  EXPECT_CONTAINS(messageOf([] { parse("group g\nobject o g world sphere 1 at 0 0 0 0 0 0\nallow o o\n"); }),
                  "s.scene:3: an allowed contact needs two different objects");
  EXPECT_CONTAINS(messageOf([] { parse("robot r tools 2 base 0 0 0 0 0 0\n"); }), "s.scene:1: tool index must be 0");
  EXPECT_CONTAINS(messageOf([] { parse("group g extra\n"); }), "s.scene:1: unexpected 'extra'");
  EXPECT_CONTAINS(messageOf([] { parse("robot r tools 1 1 base 0 0 0 0 0 0\n"); }), "s.scene:1: tool 1 listed twice");
}

TEST(Scene, MissingMeshFileIsNamedWithItsLine) {
  const std::string message = messageOf([] { parse("group g\nobject o g world mesh nope.stl at 0 0 0 0 0 0\n"); });
  EXPECT_CONTAINS(message, "s.scene:2: mesh file '");
  EXPECT_CONTAINS(message, "nope.stl' not found");
}

TEST(Scene, MissingSceneFileSaysSo) {
  EXPECT_CONTAINS(messageOf([] { loadScene(test::dataDir() / "absent.scene"); }), "cannot read scene file");
}

TEST(Scene, ValidateCatchesHandBuiltMistakes) {
  SceneDescription scene;
  scene.groups = {"g"};
  ObjectDescription object;
  object.name = "o";
  object.group = "h";
  object.shape.dimensions = {1, 1, 1};
  scene.objects.push_back(object);
  EXPECT_CONTAINS(messageOf([&] { scene.validate(); }), "object 'o': unknown group 'h'");
  scene.objects[0].group = "g";
  EXPECT_NO_THROW(scene.validate());
  scene.min_collision_distance = -1.0;
  EXPECT_CONTAINS(messageOf([&] { scene.validate(); }), "min_collision_distance");
}

TEST(Scene, MutatedFilesParseOrThrowInvalidArgument) {
  // 2000 seeded mutations (replace, delete, duplicate a byte) of the test scene: the parser either
  // accepts the text or throws std::invalid_argument with a file:line location; nothing else.
  const std::string original = test::readText(test::dataDir() / "two_robots.scene");
  const std::string alphabet = " \n#.-0123456789eabcgrotwx";
  std::uint32_t state = 2024;
  const auto next = [&](std::size_t bound) {
    state = state * 1664525u + 1013904223u;
    return static_cast<std::size_t>(state >> 8) % bound;
  };
  int accepted = 0;
  for (int i = 0; i < 2000; ++i) {
    std::string text = original;
    for (int edit = 0; edit < 3; ++edit) {
      const std::size_t at = next(text.size());
      switch (next(3)) {
        case 0: text[at] = alphabet[next(alphabet.size())]; break;
        case 1: text.erase(at, 1); break;
        default: text.insert(at, 1, text[at]); break;
      }
    }
    try {
      parseScene(text, "m.scene", test::dataDir());
      ++accepted;
    } catch (const std::invalid_argument& error) {
      EXPECT_CONTAINS(error.what(), "m.scene");
    }
  }
  EXPECT_GT(accepted, 0);  // some edits only touch comments or numbers
}

TEST(Scene, ShippedSetupsParseAndFollowTheThesisChecks) {
  const std::filesystem::path scenes = std::filesystem::path(COBRA_SOURCE_DIR) / "planning/test/scenes";
  const SceneDescription puncturing = loadScene(scenes / "puncturing.scene");
  EXPECT_EQ(puncturing.groups, (std::vector<std::string>{"macro", "micro", "ur5", "environment"}));
  EXPECT_EQ(puncturing.checks.size(), 5u);  // Algorithm 4.2, lines 8-12
  EXPECT_EQ(puncturing.robots.size(), 2u);
  const SceneDescription suturing = loadScene(scenes / "suturing.scene");
  ASSERT_EQ(suturing.robots.size(), 1u);  // Algorithm 5.1: one solver for both tools
  EXPECT_EQ(suturing.robots[0].tool_indices, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(suturing.checks.size(), 5u);
  // The world objects of both scenes build (FCL geometry) without robots moving them.
  EXPECT_NO_THROW(CollisionWorld{puncturing});
  EXPECT_NO_THROW(CollisionWorld{suturing});
}

}  // namespace
}  // namespace cobra::planning
