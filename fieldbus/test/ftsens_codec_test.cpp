// The FTSens CAN codec (cobra's own frame layout, see ftsens_codec.hpp): round trip at the
// sensor's resolution, clipping, garbled, foreign and unpaired frames, lost samples from the
// sequence numbers, configuration errors.

#include "cobra/fieldbus/ftsens_codec.hpp"

#include <gtest/gtest.h>

#include <random>

#include "cobra/test_support/test_support.hpp"

namespace {

using namespace cobra::fieldbus;

KDL::Wrench wrench(double fx, double fy, double fz, double tx, double ty, double tz) {
  return {KDL::Vector(fx, fy, fz), KDL::Vector(tx, ty, tz)};
}

// 1000 seeded random wrenches within the FTSens range: decoded within half a count per axis.
TEST(FtSensCodec, RoundTripIsExactToHalfACount) {
  FtSensCodecConfig config;
  config.address = 5;
  FtSensDecoder decoder(config);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> force(-2000.0, 2000.0), torque_xy(-40.0, 40.0), torque_z(-30.0, 30.0);
  for (int i = 0; i < 1000; ++i) {
    const KDL::Wrench w = wrench(force(rng), force(rng), force(rng), torque_xy(rng), torque_xy(rng), torque_z(rng));
    CanFrame f, t;
    EXPECT_FALSE(encodeFtSens(config, w, static_cast<std::uint8_t>(i), f, t));
    EXPECT_EQ(f.id, 0x35AU);
    EXPECT_EQ(t.id, 0x35BU);
    EXPECT_EQ(f.length, 8);
    EXPECT_EQ(decoder.push(f), FtSensFrameResult::Half);
    ASSERT_EQ(decoder.push(t), FtSensFrameResult::Sample);
    const KDL::Wrench& d = decoder.wrench();
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(d.force[axis], w.force[axis], 0.125 + 1e-9);
      EXPECT_NEAR(d.torque[axis], w.torque[axis], (axis < 2 ? 0.049 : 0.037) / 2 + 1e-9);
    }
  }
  EXPECT_EQ(decoder.samples(), 1000U);
  EXPECT_EQ(decoder.lost(), 0U);
  EXPECT_EQ(decoder.garbled(), 0U);
}

TEST(FtSensCodec, KnownBytesAndClipping) {
  FtSensCodecConfig config;
  CanFrame f, t;
  EXPECT_FALSE(encodeFtSens(config, wrench(1.0, -0.25, 0, 0.049, 0, -0.037), 7, f, t));
  // Fx = 4 counts, Fy = -1 count (0xFFFF), little-endian.
  EXPECT_EQ(f.data[0], 0x04);
  EXPECT_EQ(f.data[1], 0x00);
  EXPECT_EQ(f.data[2], 0xFF);
  EXPECT_EQ(f.data[3], 0xFF);
  EXPECT_EQ(f.data[6], 7);
  unsigned sum = 0x0A;  // the identifier's low byte 0x30A
  for (int i = 0; i < 7; ++i) sum += f.data[static_cast<std::size_t>(i)];
  EXPECT_EQ(f.data[7], static_cast<std::uint8_t>(~sum));
  EXPECT_TRUE(encodeFtSens(config, wrench(1e5, 0, 0, 0, 0, 0), 0, f, t));  // beyond 16 bits: clipped
  FtSensDecoder decoder(config);
  decoder.push(f);
  decoder.push(t);
  EXPECT_DOUBLE_EQ(decoder.wrench().force.x(), 32767 * 0.25);
  const CanFrame command = ftSensStreamCommand(config, 1);
  EXPECT_EQ(command.id, 0x200U);
  EXPECT_EQ(command.length, 2);
  EXPECT_EQ(command.data[0], kFtSensSetPeriodCommand);
  EXPECT_EQ(command.data[1], 1);
}

TEST(FtSensCodec, GarbledForeignAndUnpairedFramesAreCountedAndKeepTheLastSample) {
  FtSensCodecConfig config;
  FtSensDecoder decoder(config);
  CanFrame f, t;
  encodeFtSens(config, wrench(10, 20, 30, 1, 2, 3), 0, f, t);
  decoder.push(f);
  ASSERT_EQ(decoder.push(t), FtSensFrameResult::Sample);
  const KDL::Wrench good = decoder.wrench();

  encodeFtSens(config, wrench(-10, 0, 0, 0, 0, 0), 1, f, t);
  CanFrame bad = f;
  bad.data[3] ^= 0x01;  // a flipped bit
  EXPECT_EQ(decoder.push(bad), FtSensFrameResult::Garbled);
  bad = f;
  bad.length = 6;
  EXPECT_EQ(decoder.push(bad), FtSensFrameResult::Garbled);
  bad = f;
  bad.extended = true;
  EXPECT_EQ(decoder.push(bad), FtSensFrameResult::Garbled);
  EXPECT_EQ(decoder.push(t), FtSensFrameResult::Unpaired);  // its force half never arrived
  bad = f;
  bad.id = 0x31A;  // another board's address
  EXPECT_EQ(decoder.push(bad), FtSensFrameResult::Foreign);
  EXPECT_TRUE(decoder.wrench() == good);
  EXPECT_EQ(decoder.garbled(), 3U);
  EXPECT_EQ(decoder.unpaired(), 1U);

  // A force half followed by a torque half of another sample.
  encodeFtSens(config, wrench(1, 1, 1, 0, 0, 0), 2, f, t);
  CanFrame f3, t3;
  encodeFtSens(config, wrench(2, 2, 2, 0, 0, 0), 3, f3, t3);
  EXPECT_EQ(decoder.push(f), FtSensFrameResult::Half);
  EXPECT_EQ(decoder.push(t3), FtSensFrameResult::Unpaired);
  // Samples 1-3 never completed: the next complete one (4) reports three lost.
  CanFrame f4, t4;
  encodeFtSens(config, wrench(4, 0, 0, 0, 0, 0), 4, f4, t4);
  decoder.push(f4);
  ASSERT_EQ(decoder.push(t4), FtSensFrameResult::Sample);
  EXPECT_EQ(decoder.lost(), 3U);
  EXPECT_DOUBLE_EQ(decoder.wrench().force.x(), 4.0);
  // The sequence wraps from 255 to 0 without a loss.
  FtSensDecoder wrap(config);
  for (int s : {254, 255, 0, 1}) {
    encodeFtSens(config, wrench(s, 0, 0, 0, 0, 0), static_cast<std::uint8_t>(s), f, t);
    wrap.push(f);
    wrap.push(t);
  }
  EXPECT_EQ(wrap.samples(), 4U);
  EXPECT_EQ(wrap.lost(), 0U);
}

TEST(FtSensCodec, BadConfigurationsNameTheParameter) {
  FtSensCodecConfig config;
  config.address = 16;
  EXPECT_EQ(cobra::test_support::messageOf([&] { FtSensDecoder d(config); }),
            "FTSens codec: address = 16, expected 0-15 (4 bits of the CAN identifier)");
  config = FtSensCodecConfig{};
  config.torque_z_lsb = -1;
  EXPECT_CONTAINS(cobra::test_support::messageOf([&] { FtSensDecoder d(config); }),
                  "torque_z_lsb = -1.000000 N*m, expected > 0");
}

}  // namespace
