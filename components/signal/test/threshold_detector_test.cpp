#include "cobra/components/signal/threshold_detector.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "cobra/core/core.hpp"

namespace cobra::components {
namespace {

TEST(ThresholdDetector, RaisesEventsOnCrossingsWithHysteresis) {
  ThresholdDetector detector("Det");
  detector.setProperty("threshold", 1.0);
  detector.setProperty("hysteresis", 0.5);
  core::OutputPort<double> source{"source", "", "1"};
  core::InputPort<core::Event> events{"events", "", ""};
  core::connectPorts(source, detector.port("in"), core::ConnPolicy::buffer(16));
  core::connectPorts(detector.port("events"), events, core::ConnPolicy::buffer(16));
  core::LockstepClock clock;
  clock.add(detector, std::chrono::nanoseconds(0));
  ASSERT_TRUE(detector.configure());
  ASSERT_TRUE(detector.start());
  for (double v : {0.0, 1.2, 0.8, 1.3, 0.4, 0.2, 1.1}) source.write(v);
  clock.advance(std::chrono::milliseconds(1));
  std::vector<std::string> names;
  core::Event e;
  while (events.read(e) == core::FlowStatus::NewData) {
    names.push_back(e.name.str());
    EXPECT_EQ(e.source, "Det");
  }
  // 0.8 is inside the hysteresis band and does not re-arm; 0.4 does.
  EXPECT_EQ(names, (std::vector<std::string>{"e_above_threshold", "e_below_threshold", "e_above_threshold"}));
  EXPECT_EQ(detector.role(), core::Role::Decision);
}

}  // namespace
}  // namespace cobra::components
