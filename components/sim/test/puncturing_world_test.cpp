// The whole puncturing world of the cobra_sim components on the lockstep clock: identical seeds
// give identical traces (every recorded port), different seeds differ only in the sensor noise,
// and the update hooks of every component allocate nothing.
#include "puncturing_world.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "cobra/test_support/counting_new.hpp"

namespace cobra::components::test {
namespace {

struct Trace {
  std::vector<double> values;
  std::vector<std::string> events;
};

void record(Trace& trace, const KDL::Frame& f) {
  for (int i = 0; i < 3; ++i) trace.values.push_back(f.p(i));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) trace.values.push_back(f.M(r, c));
}
void record(Trace& trace, const KDL::Wrench& w) {
  for (int i = 0; i < 6; ++i) trace.values.push_back(w(i));
}

/// 3 s of insertion at 10 mm/s with the probe held, recording the robots' and the patient's outputs.
Trace run(int seed) {
  PuncturingWorld world(seed);
  core::InputPort<KDL::Wrench> needle_sensor{"needleSensor", "", "N"};
  core::InputPort<KDL::Wrench> probe_sensor{"probeSensor", "", "N"};
  core::InputPort<KDL::Frame> probe_pose{"probePose", "", "m"};
  core::connectPorts(world.isur.port("measWrench"), needle_sensor);
  core::connectPorts(world.ur5.port("measWrench"), probe_sensor);
  core::connectPorts(world.ur5.port("measCartPose"), probe_pose);
  EXPECT_EQ(world.start(), "");
  Trace trace;
  for (int ms = 0; ms < 3000; ++ms) {
    world.step(0.01 * ms * 1e-3);
    KDL::Wrench w;
    KDL::Frame f;
    if (needle_sensor.read(w) != core::FlowStatus::NoData) record(trace, w);
    if (probe_sensor.read(w) != core::FlowStatus::NoData) record(trace, w);
    if (world.needle_pose.read(f) != core::FlowStatus::NoData) record(trace, f);
    if (probe_pose.read(f) != core::FlowStatus::NoData) record(trace, f);
    if (world.needle_wrench.read(w) != core::FlowStatus::NoData) record(trace, w);
    trace.values.push_back(world.read(world.axial));
    for (std::string& e : world.takeEvents()) trace.events.push_back(std::to_string(ms) + " " + e);
  }
  return trace;
}

bool bitwiseEqual(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(PuncturingWorld, IdenticalSeedsGiveIdenticalTraces) {
  const Trace a = run(7);
  const Trace b = run(7);
  ASSERT_GT(a.values.size(), 3000u * 40u);
  EXPECT_TRUE(bitwiseEqual(a.values, b.values));
  EXPECT_EQ(a.events, b.events);
  // The world did something: the skin was touched and penetrated, the probe is in contact.
  auto has = [&](const std::string& name) {
    for (const std::string& e : a.events)
      if (e.ends_with(" " + name)) return true;
    return false;
  };
  EXPECT_TRUE(has("e_skin_touched"));
  EXPECT_TRUE(has("e_skin_penetrated"));
  EXPECT_TRUE(has("e_probe_contact"));
  EXPECT_TRUE(has("e_needle_visible"));

  const Trace c = run(8);  // another seed: other sensor noise, the same physics and events
  EXPECT_FALSE(bitwiseEqual(a.values, c.values));
  EXPECT_EQ(a.events, c.events);
}

TEST(PuncturingWorld, TheUpdateHooksAllocateNothing) {
  PuncturingWorld world(3);
  world.needle_monitor.setProperty("forbidden_regions", std::vector<double>{0, 0, -1, 0.1, 0, -1, 0.01});
  core::OutputPort<KDL::Frame> target{"target", "", "m"};
  core::connectPorts(target, world.needle_monitor.port("targetPose"));
  ASSERT_EQ(world.start(), "");
  target.write(world.needleAt(0.02));
  for (int ms = 0; ms < 500; ++ms) world.step(0.01 * ms * 1e-3);  // every port has carried data once
  world.patient.call<void>("startFreeze");
  (void)world.takeEvents();
  const long allocations = cobra::test_support::allocationsDuring([&] {
    for (int ms = 500; ms < 3000; ++ms) world.step(0.01 * ms * 1e-3);
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(world.isur.state(), core::State::Running);
  EXPECT_EQ(world.patient.state(), core::State::Running);
}

}  // namespace
}  // namespace cobra::components::test
