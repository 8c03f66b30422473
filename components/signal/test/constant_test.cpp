#include "cobra/components/signal/constant.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

TEST(Constant, WritesItsValueAtEveryUpdateAndFollowsItsProperty) {
  Constant constant("SetPoint");
  constant.setProperty("value", 2.5);
  core::InputPort<double> sink{"sink", "", "N"};
  core::connectPorts(constant.port("out"), sink, core::ConnPolicy::buffer(16));
  core::LockstepClock clock;
  clock.add(constant, 1ms);
  ASSERT_TRUE(constant.configure());
  ASSERT_TRUE(constant.start());
  clock.advance(3ms);
  double y = 0.0;
  int samples = 0;
  while (sink.read(y) == core::FlowStatus::NewData) {
    EXPECT_EQ(y, 2.5);
    ++samples;
  }
  EXPECT_EQ(samples, 3);
  constant.setProperty("value", -1.0);
  clock.advance(1ms);
  ASSERT_EQ(sink.read(y), core::FlowStatus::NewData);
  EXPECT_EQ(y, -1.0);
}

}  // namespace
}  // namespace cobra::components
