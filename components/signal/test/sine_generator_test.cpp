#include "cobra/components/signal/sine_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cobra/core/core.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

TEST(SineGenerator, ProducesTheSineOfSimulatedTime) {
  SineGenerator sine("Sine");
  sine.setProperty("amplitude", 2.0);
  sine.setProperty("frequency", 10.0);
  sine.setProperty("phase", 0.5);
  sine.setProperty("offset", 1.0);
  core::InputPort<double> in{"in", "", "1"};
  core::connectPorts(sine.port("out"), in, core::ConnPolicy::buffer(100));
  core::LockstepClock clock;
  clock.add(sine, 1ms);
  ASSERT_TRUE(sine.configure());
  ASSERT_TRUE(sine.start());
  clock.advance(50ms);
  double y = 0.0;
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(in.read(y), core::FlowStatus::NewData);
    EXPECT_NEAR(y, 1.0 + 2.0 * std::sin(2 * std::numbers::pi * 10.0 * k * 1e-3 + 0.5), 1e-12) << "sample " << k;
  }
  EXPECT_EQ(in.read(y), core::FlowStatus::OldData);
}

TEST(SineGenerator, RefusesNegativeFrequency) {
  SineGenerator sine("Sine");
  EXPECT_THROW(
      {
        try {
          sine.setProperty("frequency", -1.0);
        } catch (const core::Error& e) {
          EXPECT_STREQ(e.what(), "component 'Sine': property 'frequency' = -1 is out of range [0, 1e+06] (Hz)");
          throw;
        }
      },
      core::Error);
  EXPECT_EQ(sine.getProperty<double>("frequency"), 1.0);
}

}  // namespace
}  // namespace cobra::components
