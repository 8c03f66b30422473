// SimulatedFtSensBus: streams after the host's command at the commanded period, carries the
// simulated sensor's readings (bias, noise, quantisation of the FTSens preset) through the codec,
// and injects dropped samples, garbled frames, silence and receive-queue overruns.

#include "cobra/fieldbus/simulated_ftsens.hpp"

#include <gtest/gtest.h>

#include "cobra/test_support/counting_new.hpp"

namespace {

using namespace cobra::fieldbus;

struct Host {
  SimulatedFtSensBus bus{cobra::sim::ftSens(), FtSensCodecConfig{}, 11};
  FtSensDecoder decoder{FtSensCodecConfig{}};
  int drain() {
    CanFrame frame;
    int samples = 0;
    while (bus.receive(frame)) samples += decoder.push(frame) == FtSensFrameResult::Sample;
    return samples;
  }
};

TEST(SimulatedFtSens, SilentUntilCommandedThenOneSamplePerPeriod) {
  Host host;
  host.bus.setTrueWrench(KDL::Wrench(KDL::Vector(12.0, -3.0, 100.0), KDL::Vector(0.5, -0.2, 0.1)));
  host.bus.advance(0.01);
  EXPECT_EQ(host.drain(), 0);
  ASSERT_TRUE(host.bus.send(ftSensStreamCommand(FtSensCodecConfig{}, 2)));  // every 2 ms
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

TEST(SimulatedFtSens, InjectedFaultsShowInTheDecoderCounts) {
  Host host;
  host.bus.send(ftSensStreamCommand(FtSensCodecConfig{}, 1));
  host.bus.advance(0.005);
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
  host.bus.advance(0.1);  // 100 samples = 200 frames into a 64-frame queue
  EXPECT_EQ(host.drain(), 32);
  EXPECT_EQ(host.bus.overruns(), 136U);
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] {
              host.bus.advance(0.01);
              host.drain();
            }),
            0);
}

}  // namespace
