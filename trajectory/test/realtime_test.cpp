// The real-time path of every TGL type allocates nothing (ARCHITECTURE §4): evaluation of polynomials,
// one-axis, multi-point, multi-axis and Cartesian trajectories, and building a stop polynomial,
// counted with a replacement operator new around many calls, inside and outside [0, T].

#include <gtest/gtest.h>

#include <vector>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/trajectory/tgl.hpp"

namespace {

using cobra::test_support::allocationsDuring;
namespace tgl = cobra::trajectory;

constexpr int kCalls = 2000;  // evaluations per type, spread over [-0.5 s, T + 0.5 s]

double sampleTime(int i, double duration) { return -0.5 + (duration + 1.0) * i / kCalls; }

TEST(RealTime, OneAxisEvaluationAllocatesNothing) {
  const tgl::Polynomial polynomial(7, tgl::Conditions(tgl::State{0, 1, 2, 3}, tgl::State{1}), 2.0);
  const tgl::PolynomialTrajectory trajectory(5, tgl::Conditions(0.0, 1.0), 2.0);
  const std::vector<double> waypoints{0.0, 1.0, -1.0, 0.5}, durations{1.0, 2.0, 1.0};
  const tgl::MultiPointLinearTrajBlends blends(waypoints, durations, 0.3, 5);
  tgl::State out;
  double sink = 0.0;
  EXPECT_EQ(allocationsDuring([&] {
              for (int i = 0; i < kCalls; ++i) {
                polynomial.evaluate(sampleTime(i, 2.0), out);
                sink += out.position;
                trajectory.evaluate(sampleTime(i, 2.0), out);
                sink += out.velocity;
                blends.evaluate(sampleTime(i, blends.duration()), out);
                sink += out.acceleration;
              }
            }),
            0);
  EXPECT_NE(sink, 0.0);
}

TEST(RealTime, StopPolynomialIsBuiltWithoutAllocating) {
  tgl::State out;
  EXPECT_EQ(allocationsDuring([&] {
              for (int i = 0; i < kCalls; ++i) {
                const tgl::Polynomial stop = tgl::Polynomial::stop(tgl::State{0.1 * i, 1.0, -0.5}, 0.3);
                stop.evaluate(0.1, out);
              }
            }),
            0);
}

TEST(RealTime, MultiAxisAndCartesianEvaluationAllocateNothing) {
  const tgl::MultiAxisTrajectory axes(tgl::MultiAxisPath({{0, 0, 0}, {1, -1, 0.5}, {2, 0, 0}}),
                                      tgl::AxisLimits{{1, 1, 1}, {0.2, 0.3, 0.4}}, 4);
  const std::vector<KDL::Frame> frames{
      KDL::Frame::Identity(), KDL::Frame(KDL::Rotation::RPY(0.5, 0.2, 1.0), KDL::Vector(0.1, 0.2, 0.0)),
      KDL::Frame(KDL::Rotation::RPY(-0.5, 0.4, 2.5), KDL::Vector(0.3, 0.1, 0.2))};
  const tgl::CartesianTrajectory cartesian(frames, tgl::CartesianLimits{}, 5);
  std::vector<tgl::State> states(axes.axisCount());
  std::vector<KDL::Frame> poses(1);
  std::vector<KDL::Twist> twists(1);
  EXPECT_EQ(allocationsDuring([&] {
              for (int i = 0; i < kCalls; ++i) {
                axes.evaluate(sampleTime(i, axes.duration()), states);
                cartesian.evaluate(sampleTime(i, cartesian.duration()), poses, twists);
              }
            }),
            0);
  EXPECT_TRUE(KDL::Equal(poses[0], frames.back(), 1e-9));
}

TEST(RealTime, CartesianStopIsBuiltAndEvaluatedWithoutAllocating) {
  const tgl::CartesianTrajectory moving(
      std::vector<KDL::Frame>{KDL::Frame::Identity(),
                              KDL::Frame(KDL::Rotation::RPY(0.5, 0.2, 1.0), KDL::Vector(0.1, 0.2, 0.0))},
      tgl::CartesianLimits{}, 5);
  KDL::Frame pose;
  KDL::Twist twist, acceleration;
  double sink = 0.0;
  EXPECT_EQ(allocationsDuring([&] {
              for (int i = 0; i < kCalls; ++i) {
                moving.evaluate(sampleTime(i, moving.duration()), 0, pose, twist, acceleration);
                const tgl::CartesianStop stop(pose, twist, acceleration, 0.2);
                stop.evaluate(0.1, pose, twist);
                sink += pose.p.x();
              }
            }),
            0);
  EXPECT_NE(sink, 0.0);
}

TEST(RealTime, TheCounterSeesAllocations) {
  // Proves the zero counts above are measurements: building a trajectory does allocate.
  EXPECT_GT(allocationsDuring([] { tgl::PolynomialTrajectory t(5, tgl::Conditions(0.0, 1.0)); }), 0);
}

}  // namespace
