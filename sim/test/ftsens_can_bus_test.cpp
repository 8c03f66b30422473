// FtSensCanBus: streams after the host's command at the commanded period, carries the simulated
// sensor's readings (bias, noise, quantisation of the FTSens preset) through the codec, injects
// dropped samples, garbled frames, silence and receive-queue overruns; with a clock attached the
// host sees the frames of earlier instants only, and nothing once the world side detached.

#include "cobra/sim/ftsens_can_bus.hpp"

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"

namespace {

using namespace cobra::fieldbus;
using cobra::sim::FtSensCanBus;

struct Host {
  FtSensCanBus bus{cobra::sim::ftSens(), FtSensCodecConfig{}, 11};
  FtSensDecoder decoder{FtSensCodecConfig{}};
  int drain() {
    CanFrame frame;
    int samples = 0;
    while (bus.receive(frame)) samples += decoder.push(frame) == FtSensFrameResult::Sample;
    return samples;
  }
};

TEST(FtSensCanBus, SilentUntilCommandedThenOneSamplePerPeriod) {
  Host host;
  host.bus.setTrueWrench(KDL::Wrench(KDL::Vector(12.0, -3.0, 100.0), KDL::Vector(0.5, -0.2, 0.1)));
  host.bus.advance(0.01);
  EXPECT_EQ(host.drain(), 0);
  ASSERT_TRUE(host.bus.send(ftSensStreamCommand(FtSensCodecConfig{}, 2)));  // every 2 ms
  EXPECT_DOUBLE_EQ(host.bus.streamingPeriod(), 0.0);                        // taken at the next step
  host.bus.advance(0.0);
  EXPECT_DOUBLE_EQ(host.bus.streamingPeriod(), 0.002);
  int samples = 0;
  for (int i = 0; i < 100; ++i) {
    host.bus.advance(1e-3);
    samples += host.drain();
  }
  EXPECT_EQ(samples, 50);
  // The decoded wrench is the sensor's reading: within noise and a count of the truth.
  EXPECT_NEAR(host.decoder.wrench().force.x(), 12.0, 1.0);
  EXPECT_NEAR(host.decoder.wrench().force.z(), 100.0, 1.0);
  EXPECT_NEAR(host.decoder.wrench().torque.x(), 0.5, 0.1);
  EXPECT_EQ(host.decoder.wrench().force.y(), host.bus.sensor().reading().wrench.force.y());  // same counts
}

TEST(FtSensCanBus, InjectedFaultsShowInTheDecoderCounts) {
  Host host;
  host.bus.send(ftSensStreamCommand(FtSensCodecConfig{}, 1));
  host.bus.advance(0.005);  // the command is taken, then 5 samples fall due
  EXPECT_EQ(host.drain(), 5);
  host.bus.dropSamples(3);
  host.bus.advance(0.005);
  EXPECT_EQ(host.drain(), 2);
  EXPECT_EQ(host.decoder.lost(), 3U);
  host.bus.garbleFrames(1);
  host.bus.advance(0.002);
  EXPECT_EQ(host.drain(), 1);  // the garbled force half takes its sample with it
  EXPECT_EQ(host.decoder.garbled(), 1U);
  EXPECT_EQ(host.decoder.unpaired(), 1U);
  host.bus.setSilent(true);
  host.bus.advance(0.01);
  EXPECT_EQ(host.drain(), 0);
  host.bus.setSilent(false);
  host.bus.advance(0.1);  // 100 samples = 200 frames into a 64-frame queue: the first 64 stay
  EXPECT_EQ(host.drain(), 32);
  EXPECT_EQ(host.bus.overruns(), 136U);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              host.bus.advance(0.01);
              host.drain();
            }),
            0);
}

TEST(FtSensCanBus, WithAClockTheHostSeesTheFramesOfEarlierInstantsOnly) {
  Host host;
  std::int64_t now = 0;  // ns
  host.bus.link().attach([&] { return now; });
  ASSERT_TRUE(host.bus.send(ftSensStreamCommand(FtSensCodecConfig{}, 1)));
  host.bus.advance(1e-3);  // same instant as the command: not taken yet
  EXPECT_DOUBLE_EQ(host.bus.streamingPeriod(), 0.0);
  now = 1'000'000;
  host.bus.advance(1e-3);  // the command is taken and a sample falls due, stamped 1 ms
  EXPECT_DOUBLE_EQ(host.bus.streamingPeriod(), 0.001);
  EXPECT_EQ(host.drain(), 0);  // the host in the same instant does not see it
  now = 2'000'000;
  EXPECT_EQ(host.drain(), 1);  // the next instant it does, before or after the world's step
  host.bus.advance(1e-3);
  EXPECT_EQ(host.drain(), 0);
  host.bus.link().detach();  // the sensor's component is gone: nothing flows any more
  now = 3'000'000;
  EXPECT_EQ(host.drain(), 0);
  EXPECT_FALSE(host.bus.send(ftSensStreamCommand(FtSensCodecConfig{}, 1)));
}

}  // namespace
