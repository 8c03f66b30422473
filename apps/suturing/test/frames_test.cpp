// The suturing application's tool frames (apps/suturing/frames.lua, the one place they are given)
// agree with the suturing scene's geometry: the left tool's frame is the tip of the scene's stick,
// so the pose the robot measures, the planner plans and the wound sees is where the stick ends; the
// right one is the Endo Stitch's tip held off its singular vertical.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include <kdl/frames.hpp>

#include "cobra/planning/scene.hpp"
#include "cobra/script/lua_state.hpp"

namespace {

const std::string kSource = COBRA_SOURCE_DIR;

/// frames.lua's frame `name` ({x, y, z, qx, qy, qz, qw}) as a KDL frame.
KDL::Frame luaFrame(cobra::script::LuaState& lua, const std::string& name) {
  std::array<double, 7> v{};
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = std::stod(lua.evaluate("string.format('%.17g', frames." + name + "[" + std::to_string(i + 1) + "])"));
  return KDL::Frame(KDL::Rotation::Quaternion(v[3], v[4], v[5], v[6]), KDL::Vector(v[0], v[1], v[2]));
}

class SuturingFrames : public ::testing::Test {
 protected:
  void SetUp() override {
    lua.run("frames = dofile('" + kSource + "/apps/suturing/frames.lua')");
    right = luaFrame(lua, "right_tool");
    left = luaFrame(lua, "left_tool");
  }
  cobra::script::LuaState lua;
  KDL::Frame right, left;
};

TEST_F(SuturingFrames, TheLeftToolIsTheTipOfTheScenesStick) {
  const cobra::planning::SceneDescription scene = cobra::planning::loadScene(kSource + "/apps/suturing/deployment/suturing.scene");
  const std::size_t index = scene.objectIndex("stick");
  ASSERT_NE(index, cobra::planning::SceneDescription::npos) << "the suturing scene has no object 'stick'";
  const cobra::planning::ObjectDescription& stick = scene.objects[index];
  // On the gripper (the I-SUR's tool 1, link 11), a cylinder along its axis from where it grasps it.
  EXPECT_EQ(stick.attached_to.robot_name, "isur");
  EXPECT_EQ(stick.attached_to.link_index, 11u);
  ASSERT_EQ(stick.shape.kind, cobra::planning::ShapeKind::Cylinder);
  const double length = stick.shape.dimensions[1];
  EXPECT_NEAR(length, 0.15, 1e-12);
  const KDL::Vector tip = stick.offset * KDL::Vector(0.0, 0.0, length / 2);
  const KDL::Vector grasp = stick.offset * KDL::Vector(0.0, 0.0, -length / 2);
  EXPECT_LT((tip - left.p).Norm(), 1e-12) << "stick tip at z " << tip.z() << " m, left tool at z " << left.p.z() << " m";
  EXPECT_LT(grasp.Norm(), 1e-12) << "the stick starts where the gripper holds it";
  // The datum's z (into the skin) leans 0.6 rad from the gripper's axis (the stick's).
  EXPECT_NEAR(std::acos(KDL::dot(left.M.UnitZ(), KDL::Vector(0, 0, 1))), 0.6, 1e-12);
}

TEST_F(SuturingFrames, TheRightToolIsTheEndoStitchTipHeldOffTheVertical) {
  // The Endo Stitch's tip (no offset): the instrument (pointing along the model tip frame's x) 21
  // deg off the datum's z, so that the datum pointing straight down keeps it off its wrist's
  // singular vertical.
  EXPECT_LT(right.p.Norm(), 1e-15);
  const double off_vertical = std::acos(KDL::dot(KDL::Vector(1, 0, 0), right.M.UnitZ()));
  EXPECT_NEAR(off_vertical, 3.141592653589793 / 2 - 1.2, 1e-9);
}

}  // namespace
