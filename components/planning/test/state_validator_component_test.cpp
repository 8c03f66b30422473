// The StateValidator component (thesis §5.4.2) on the lockstep clock with the real robot models:
// valid set-point pairs pass, invalid ones are replaced by the last valid pair, events mark the
// changes, minDistance follows; configuration errors name the property.

#include "cobra/components/planning/state_validator_component.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "cobra/core/core.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"
#include "../../../planning/test/puncturing_tools.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;
constexpr double kPi = std::numbers::pi;

using planning::test::needleDown;
using planning::test::probeDown;
std::string scenes() { return planning::test::scenes().string(); }

struct Bench {
  StateValidatorComponent validator{"Validator"};
  core::LockstepClock clock;
  core::OutputPort<KDL::Frame> in_1{"in1", "", "m"};
  core::OutputPort<KDL::Frame> in_2{"in2", "", "m"};
  core::InputPort<KDL::Frame> out_1{"out1", "", "m"};
  core::InputPort<KDL::Frame> out_2{"out2", "", "m"};
  core::InputPort<double> min_distance{"minDistance", "", "m"};
  core::InputPort<KDL::Frame> held_1{"held1", "", "m"};
  core::InputPort<KDL::Frame> held_2{"held2", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};

  explicit Bench(const std::string& scene = "puncturing.scene") {
    validator.setProperty("models_folder", scenes());
    validator.setProperty("scene_file", scene);
    clock.add(validator, 1ms);
    core::connectPorts(in_1, validator.port("desPoseIn_1"));
    core::connectPorts(in_2, validator.port("desPoseIn_2"));
    core::connectPorts(validator.port("desPoseOut_1"), out_1);
    core::connectPorts(validator.port("desPoseOut_2"), out_2);
    core::connectPorts(validator.port("minDistance"), min_distance);
    core::connectPorts(validator.port("heldPose_1"), held_1);
    core::connectPorts(validator.port("heldPose_2"), held_2);
    core::connectPorts(validator.port("events"), events, core::ConnPolicy::buffer(64));
    EXPECT_TRUE(validator.configure());
    EXPECT_TRUE(validator.start());
  }
  std::vector<std::string> takeEvents() {
    std::vector<std::string> names;
    core::Event e;
    while (events.read(e) == core::FlowStatus::NewData) names.push_back(e.name.str());
    return names;
  }
  /// Writes a pair, steps 1 ms, returns what came out.
  std::pair<KDL::Frame, KDL::Frame> send(const KDL::Frame& a, const KDL::Frame& b) {
    in_1.write(a);
    in_2.write(b);
    clock.advance(1ms);
    std::pair<KDL::Frame, KDL::Frame> out;
    EXPECT_EQ(out_1.read(out.first), core::FlowStatus::NewData);
    EXPECT_EQ(out_2.read(out.second), core::FlowStatus::NewData);
    return out;
  }
};

TEST(StateValidatorComponent, PassesValidPairsHoldsTheLastValidOneOtherwise) {
  Bench b;
  const KDL::Frame needle = needleDown(0.0, 0.0, 0.2);
  const KDL::Frame probe = probeDown(-0.1, 0.0, 0.12);
  auto out = b.send(needle, probe);
  EXPECT_EQ(out.first, needle);
  EXPECT_EQ(out.second, probe);
  double distance = 0.0;
  ASSERT_EQ(b.min_distance.read(distance), core::FlowStatus::NewData);
  EXPECT_GT(distance, 0.005);
  EXPECT_TRUE(b.takeEvents().empty());
  KDL::Frame held;
  EXPECT_EQ(b.held_1.read(held), core::FlowStatus::NoData);  // nothing held while the pairs are valid

  // The needle pushed into the phantom: the last valid pair goes on, once e_state_invalid, and
  // is the held pair (for the set-points' producers to re-sync to) in each step that rejects.
  out = b.send(needleDown(0.05, 0.0, 0.05), probe);
  EXPECT_EQ(out.first, needle);
  EXPECT_EQ(out.second, probe);
  ASSERT_EQ(b.held_1.read(held), core::FlowStatus::NewData);
  EXPECT_EQ(held, needle);
  ASSERT_EQ(b.held_2.read(held), core::FlowStatus::NewData);
  EXPECT_EQ(held, probe);
  ASSERT_EQ(b.min_distance.read(distance), core::FlowStatus::NewData);
  EXPECT_LE(distance, 0.005);
  out = b.send(needleDown(0.05, 0.0, 0.06), probe);
  EXPECT_EQ(out.first, needle);
  EXPECT_EQ(b.held_1.read(held), core::FlowStatus::NewData);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_state_invalid"}));
  EXPECT_CONTAINS(b.validator.call<std::string>("lastReason"), "too close: micro/environment");

  // Unreachable: held too, NaN distance.
  out = b.send(needle, probeDown(-0.95, 0.0, 0.3));
  EXPECT_EQ(out.second, probe);
  ASSERT_EQ(b.min_distance.read(distance), core::FlowStatus::NewData);
  EXPECT_TRUE(std::isnan(distance));
  EXPECT_EQ(b.validator.call<std::string>("lastReason"), "unreachable: robot 'ur5' has no IK solution");

  // Valid again: passed on, once e_state_valid.
  const KDL::Frame needle_2 = needleDown(0.02, 0.0, 0.18);
  (void)b.held_1.read(held);
  out = b.send(needle_2, probe);
  EXPECT_EQ(out.first, needle_2);
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_state_valid"}));
  EXPECT_EQ(b.held_1.read(held), core::FlowStatus::OldData);  // valid: nothing held
}

TEST(StateValidatorComponent, UpdateAllocatesNothing) {
  Bench b;
  const KDL::Frame needle = needleDown(0.0, 0.0, 0.2);
  const KDL::Frame probe = probeDown(-0.1, 0.0, 0.12);
  b.send(needle, probe);
  b.send(needleDown(0.05, 0.0, 0.05), probe);
  for (const KDL::Frame& n : {needleDown(0.01, 0.0, 0.2), needleDown(0.05, 0.0, 0.05), needleDown(0.0, 0.0, -0.3)}) {
    b.in_1.write(n);
    b.in_2.write(probe);
    EXPECT_EQ(test_support::allocationsDuring([&] { b.clock.advance(1ms); }), 0);
  }
}

TEST(StateValidatorComponent, NothingIsWrittenBeforeTheFirstValidPair) {
  Bench b;
  b.in_1.write(needleDown(0.05, 0.0, 0.05));
  b.in_2.write(probeDown(-0.1, 0.0, 0.12));
  b.clock.advance(1ms);
  KDL::Frame f;
  EXPECT_EQ(b.out_1.read(f), core::FlowStatus::NoData);
  EXPECT_EQ(b.held_1.read(f), core::FlowStatus::NoData);  // no valid pair to hold at
  EXPECT_EQ(b.takeEvents(), (std::vector<std::string>{"e_state_invalid"}));
}

// Algorithm 5.1 through the component: the two-armed I-SUR, one solver for both tools.
TEST(StateValidatorComponent, SuturingPairsAreCheckedWithOneSolver) {
  Bench b("suturing.scene");
  planning::IsurSuturingModel isur;
  KDL::JntArray q = planning::IsurSuturingModel::defaultSeed();
  q(5) = 0.8;
  q(6) = 0.6;
  KDL::Frame stitch, gripper;
  ASSERT_EQ(isur.solver().forward(q, stitch, gripper), kinematics::IkStatus::Ok);
  const KDL::Frame base(KDL::Vector(0, 0, 1.0));  // suturing.scene's I-SUR base
  const auto out = b.send(base * stitch, base * gripper);
  EXPECT_EQ(out.first, base * stitch);
  EXPECT_TRUE(b.takeEvents().empty());
}

TEST(StateValidatorComponent, BadPropertiesAreRefusedNamingComponentAndProperty) {
  StateValidatorComponent validator("Validator");
  validator.setProperty("models_folder", scenes());
  validator.setProperty("scene_file", std::string("absent.scene"));
  core::Result result = validator.configure();
  EXPECT_FALSE(result);
  EXPECT_CONTAINS(result.message, "component 'Validator': property scene_file:");
  EXPECT_CONTAINS(result.message, "absent.scene");
  validator.setProperty("scene_file", std::string("puncturing.scene"));
  validator.setProperty("isur_mesh_names", std::string("- - isur_yaw.stl"));
  result = validator.configure();
  EXPECT_FALSE(result);
  EXPECT_CONTAINS(result.message, "component 'Validator': property isur_mesh_names: mesh file '" + scenes() +
                                      "/isur_yaw.stl' does not exist");
  validator.setProperty("isur_mesh_names", std::string());
  EXPECT_TRUE(validator.configure());
}

}  // namespace
}  // namespace cobra::components
