// A robot drawn from its kinematics solver's DH chain (studio/src/chain_robot.cpp) on the Puma 260
// task: its link frames in a frame (computed without allocating) put the tool where the MuJoCo
// world's ground truth has it, the
// model's shapes join the link frames (each leg's ends on two frames' origins), and a wrong
// `kinematics` entry is one line naming the app's file:line and what was expected.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/run/port_tap.hpp"
#include "cobra/run/runner.hpp"
#include "cobra/studio/bridge.hpp"
#include "cobra/studio/json.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::studio {
namespace {

const std::string kSource = COBRA_SOURCE_DIR;

// Forwards to the bridge; at each frame the bridge publishes, keeps the world's true tool pose.
class ToolProbe final : public run::RunObserver {
 public:
  explicit ToolProbe(VisualizerBridge& bridge) : bridge_(bridge) {}
  void attach(const run::RunContext& run) override {
    bridge_.attach(run);
    tool_ = std::make_unique<run::Tap<KDL::Frame>>(run.registry, "World.toolPose", "test", "probe", "KDL.Frame");
  }
  void step(const run::StepView& now) override {
    const long before = bridge_.stats().published, news = test_support::newCalls();
    bridge_.step(now);
    allocations += test_support::newCalls() - news;
    if (bridge_.stats().published != before) tool_->read(tool);
  }
  void event(double t, const std::string& source, const std::string& name) override { bridge_.event(t, source, name); }
  bool nextInput(std::size_t& index) override { return bridge_.nextInput(index); }
  std::vector<std::string> finished(const run::RunResult& result) override { return bridge_.finished(result); }

  KDL::Frame tool;
  long allocations = 0;  // in the bridge's steps

 private:
  VisualizerBridge& bridge_;
  std::unique_ptr<run::Tap<KDL::Frame>> tool_;
};

KDL::Frame poseOf(const json::Json& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(p[3].get<double>(), p[4].get<double>(), p[5].get<double>(), p[6].get<double>()),
                    KDL::Vector(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()));
}

TEST(ChainRobot, ThePuma260IsDrawnFromItsKinematicsChainAtTheMeasuredJoints) {
  VisualizerBridge bridge;
  ToolProbe probe(bridge);
  run::RunOptions options;
  options.app = kSource + "/apps/puma260";
  options.time_limit = 3.0;  // s: the arm moves from its nest towards the ready position
  options.observer = &probe;
  const run::RunResult result = run::runApp(options);
  ASSERT_EQ(result.outcome, run::Outcome::TimeLimit) << result.reason;
  EXPECT_EQ(probe.allocations, 0) << "the chain's link frames are computed without allocating";
  int status = 0;
  const json::Json model = json::parse(bridge.model(status));
  ASSERT_EQ(status, 200);
  ASSERT_EQ(model["robots"].size(), 1u);
  EXPECT_EQ(model["robots"][0]["name"], "puma");
  EXPECT_EQ(model["robots"][0]["joints"].size(), 6u);
  EXPECT_EQ(model["robots"][0]["links"], 8) << "DH frames 0..6 and the tool";
  std::uint64_t seq = 0;
  std::string text;
  ASSERT_TRUE(bridge.latestFrame(seq, text));
  const json::Json frame = json::parse(text);
  const json::Json& links = frame["robots"]["puma"]["links"];
  ASSERT_EQ(links.size(), 8u) << text;
  std::vector<KDL::Frame> world;
  for (const json::Json& l : links) world.push_back(poseOf(l));
  // The drawn tool tip (Kin's base_frame · DH chain · tool_frame) is where the MuJoCo world has its
  // tool_tip site (puma260.xml's own body tree): two models of the arm agree at the measured joints.
  const KDL::Vector tip = world.back().p;
  EXPECT_LT((tip - probe.tool.p).Norm(), 2e-3) << "drawn tip " << tip.x() << " " << tip.y() << " " << tip.z()
                                                << ", the world's " << probe.tool.p.x() << " " << probe.tool.p.y() << " "
                                                << probe.tool.p.z();
  EXPECT_GT(tip.Norm(), 0.2) << "the arm is drawn away from its base";
  // Every shape of the arm is a cylinder on one of its links; each leg's ends lie on link origins
  // (the joint housings are centred on them), so the drawn arm is joined at every frame.
  std::size_t legs = 0, housings = 0;
  for (const json::Json& o : model["objects"]) {
    ASSERT_EQ(o["robot"], "puma") << o.dump();
    ASSERT_EQ(o["shape"]["type"], "cylinder") << o.dump();
    const auto link = o["link"].get<std::size_t>();
    ASSERT_LT(link, world.size());
    const KDL::Frame placed = world[link] * poseOf(o["pose"]);
    const double half = o["shape"]["size"][1].get<double>() / 2.0;
    const KDL::Vector a = placed * KDL::Vector(0, 0, -half), b = placed * KDL::Vector(0, 0, half);
    if (o["group"] == "puma.joints") {
      ++housings;
      EXPECT_LT(((a + b) / 2.0 - world[link].p).Norm(), 1e-9) << o.dump();
      continue;
    }
    ++legs;
    const auto onAnOrigin = [&](const KDL::Vector& v) {
      for (const KDL::Frame& f : world)
        if ((f.p - v).Norm() < 1e-6) return true;
      return false;
    };
    // A leg along d ends at the elbow of its row, which is no frame's origin: one end is enough.
    EXPECT_TRUE(onAnOrigin(a) || onAnOrigin(b)) << o.dump();
  }
  EXPECT_EQ(housings, 6u);
  // Puma 260: d1, d3, d4, d6 and a2 (a3 = 0) and the tool (18 mm flange to sensor + 100 mm to the tip).
  EXPECT_EQ(legs, 6u);
}

// The line of apps/puma260/puma260.lua declaring the studio's robot.
int robotLine() {
  std::ifstream in(kSource + "/apps/puma260/puma260.lua");
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find("robots = { puma = ") != std::string::npos) return n;
  return 0;
}

std::string kinematicsError(const std::string& component) {
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kSource + "/apps/puma260";
  options.time_limit = 0.1;  // s: the chain is read at setup
  options.extra_lua = "run.studio.robots.puma.kinematics = '" + component + "'";
  options.observer = &bridge;
  return test_support::messageOf([&] { run::runApp(options); });
}

TEST(ChainRobot, AKinematicsEntryThatIsNoSolverIsOneLineWithTheAppsFileAndLine) {
  const std::string at = kSource + "/apps/puma260/puma260.lua:" + std::to_string(robotLine()) + ": run.studio.robots.puma: ";
  const std::string unknown = kinematicsError("Kinn");
  EXPECT_EQ(unknown.rfind(at + "unknown component 'Kinn'; did you mean 'Kin'?", 0), 0u) << unknown;
  EXPECT_EQ(kinematicsError("Puma").rfind(at + "component 'Puma' has no property 'robot'", 0), 0u) << kinematicsError("Puma");
}

TEST(ChainRobot, ARobotOfTheSceneIsDrawnFromItsModelNotFromAKinematicsEntry) {
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kSource + "/apps/puncturing";
  options.time_limit = 0.1;  // s
  options.extra_lua = "run.studio.robots.ur5 = { 'UR5.measJointPosition', kinematics = 'NeedleFrames' }";
  options.observer = &bridge;
  const std::string message = test_support::messageOf([&] { run::runApp(options); });
  EXPECT_NE(message.find(": run.studio.robots.ur5: kinematics = \"NeedleFrames\" draws a robot no scene models; ur5 is a "
                         "robot of the scene of NeedlePlanner (drawn from its model)"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace cobra::studio
