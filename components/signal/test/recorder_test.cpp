#include "cobra/components/signal/recorder.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

TEST(Recorder, KeepsTimedSamplesUpToCapacityAndCountsTheRest) {
  Recorder recorder("Rec");
  recorder.setProperty("capacity", 3);
  core::OutputPort<double> source{"source", "", "1"};
  core::connectPorts(source, recorder.port("in"), core::ConnPolicy::buffer(8));
  core::LockstepClock clock;
  clock.add(recorder, 0ns);
  ASSERT_TRUE(recorder.configure());
  ASSERT_TRUE(recorder.start());
  for (int i = 0; i < 5; ++i) {
    source.write(i * 10.0);
    clock.advance(2ms);  // the triggered recorder runs in the instant the clock reaches next
  }
  ASSERT_EQ(recorder.samples().size(), 3u);
  EXPECT_EQ(recorder.samples()[2].value, 20.0);
  EXPECT_EQ(recorder.getProperty<int>("dropped"), 2);
  EXPECT_EQ(recorder.call<int>("count"), 3);
  recorder.call<void>("clear");
  EXPECT_EQ(recorder.call<int>("count"), 0);
  EXPECT_EQ(recorder.getProperty<int>("dropped"), 0);
  source.write(5.0);
  clock.advance(2ms);
  EXPECT_EQ(recorder.call<int>("count"), 1);
}

TEST(Recorder, DroppedIsReadOnly) {
  Recorder recorder("Rec");
  try {
    recorder.setProperty("dropped", 0);
    FAIL() << "expected an error";
  } catch (const core::Error& e) {
    EXPECT_STREQ(e.what(), "component 'Rec': property 'dropped' is read-only; it reports a value and cannot be set");
  }
}

}  // namespace
}  // namespace cobra::components
