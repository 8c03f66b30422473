#include "cobra/components/signal/gain.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"

namespace cobra::components {
namespace {

TEST(Gain, ScalesEverySampleOnItsEventPort) {
  Gain gain("Gain");
  gain.setProperty("k", -3);  // an int is accepted for a double property
  core::OutputPort<double> source{"source", "", "1"};
  core::InputPort<double> sink{"sink", "", "1"};
  core::connectPorts(source, gain.port("in"), core::ConnPolicy::buffer(8));
  core::connectPorts(gain.port("out"), sink, core::ConnPolicy::buffer(8));
  core::LockstepClock clock;
  clock.add(gain, std::chrono::nanoseconds(0));
  ASSERT_TRUE(gain.configure());
  ASSERT_TRUE(gain.start());
  source.write(1.0);
  source.write(2.5);
  clock.advance(std::chrono::milliseconds(1));
  double y = 0.0;
  ASSERT_EQ(sink.read(y), core::FlowStatus::NewData);
  EXPECT_EQ(y, -3.0);
  ASSERT_EQ(sink.read(y), core::FlowStatus::NewData);
  EXPECT_EQ(y, -7.5);
  EXPECT_EQ(sink.read(y), core::FlowStatus::OldData);
  EXPECT_EQ(gain.updateCount(), 1u);  // both samples in one triggered update
}

TEST(Gain, DoesNotRunWithoutInput) {
  Gain gain("Gain");
  core::LockstepClock clock;
  clock.add(gain, std::chrono::nanoseconds(0));
  ASSERT_TRUE(gain.configure());
  ASSERT_TRUE(gain.start());
  clock.advance(std::chrono::seconds(1));
  EXPECT_EQ(gain.updateCount(), 0u);
}

}  // namespace
}  // namespace cobra::components
