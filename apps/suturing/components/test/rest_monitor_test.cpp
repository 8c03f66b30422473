// RestMonitor on the lockstep clock, fed two tool poses by the test: tools at rest are answered
// once they have stayed so for the window after the ask;
// a tool springing back (a critically damped return of 4 mm, the stick let go of the thread) is at
// rest only once it has slowed below tolerance / window, and what it still moves after the answer
// is below the tolerance; a slow turn alone keeps it moving; no answer before both poses arrived;
// bad properties refused naming them; stepping and answering allocate nothing.
#include "cobra/components/suturing/rest_monitor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cobra/core/lockstep_clock.hpp"
#include "cobra/test_support/counting_new.hpp"

namespace cobra::components::test {
namespace {

using namespace std::chrono_literals;

struct Bench {
  core::LockstepClock clock;
  RestMonitor monitor{"Rest"};
  core::OutputPort<KDL::Frame> right{"right", "", "m"}, left{"left", "", "m"};
  core::InputPort<core::Event> events{"events", "", ""};
  std::vector<double> answers;  // s: when e_at_rest came

  Bench() {
    clock.add(monitor, 1ms);
    core::connectPorts(right, monitor.port("rightMeasPose"));
    core::connectPorts(left, monitor.port("leftMeasPose"));
    core::connectPorts(monitor.port("events"), events, core::ConnPolicy::buffer(8));
  }
  void start() {
    ASSERT_TRUE(monitor.configure());
    ASSERT_TRUE(monitor.start());
  }
  double t() { return std::chrono::duration<double>(clock.now()).count(); }
  /// One 1 ms step with the tools at these poses.
  void step(const KDL::Frame& r, const KDL::Frame& l) {
    right.write(r);
    left.write(l);
    clock.advance(1ms);
    for (core::Event e; events.read(e) == core::FlowStatus::NewData;) {
      EXPECT_EQ(e.name.str(), "e_at_rest");
      answers.push_back(t());
    }
  }
};

const KDL::Frame kRight(KDL::Rotation::RPY(3.14, 0.0, 0.2), KDL::Vector(0.17, 0.0, 0.09));
const KDL::Frame kLeft(KDL::Rotation::RPY(3.14, 0.0, -0.1), KDL::Vector(0.15, 0.02, 0.07));

TEST(RestMonitor, ToolsAtRestAreAnsweredOnceTheyStayedSoForTheWindowAfterTheAsk) {
  Bench b;
  b.start();
  for (int i = 0; i < 300; ++i) b.step(kRight, kLeft);  // still for 0.3 s: longer than the 0.2 s window
  EXPECT_TRUE(b.answers.empty());                        // nobody asked
  b.monitor.call<void>("askAtRest");
  const double asked = b.t();
  for (int i = 0; i < 300; ++i) b.step(kRight, kLeft);
  ASSERT_EQ(b.answers.size(), 1u);  // one answer per ask
  EXPECT_NEAR(b.answers[0] - asked, 0.2, 0.0015);
}

// The stick let go of a 4 N pull on its 1000 N/m, 4 kg admittance (critically damped, 15.8 rad/s):
// it returns 4 mm, starting at rest. Asked as it is let go (still for 0.3 s before), the answer
// comes once it moves slower than 0.5 mm/s, not at once, and it moves less than the tolerance
// (0.1 mm) from then on.
TEST(RestMonitor, ASpringingToolIsAtRestOnlyOnceItHasSlowedDown) {
  const double omega = std::sqrt(1000.0 / 4.0), x0 = 0.004;
  auto left = [&](double s) {  // the stick s seconds after the release (held 4 mm off before it)
    KDL::Frame f = kLeft;
    f.p.y(f.p.y() + x0 * (1.0 + omega * s) * std::exp(-omega * s));
    return f;
  };
  Bench b;
  b.start();
  for (int i = 0; i < 300; ++i) b.step(kRight, left(0.0));  // pulled by the thread, still
  b.monitor.call<void>("askAtRest");
  const double asked = b.t();
  double answered_at = -1.0, y_then = 0.0;
  for (int i = 1; i <= 2000; ++i) {
    const KDL::Frame l = left(i * 1e-3);
    b.step(kRight, l);
    if (answered_at < 0.0 && !b.answers.empty()) answered_at = b.answers.front() - asked, y_then = l.p.y();
  }
  ASSERT_EQ(b.answers.size(), 1u);
  // The displacement's speed x0·ω²·s·e^(-ω s) falls below 0.5 mm/s about 0.43 s after the release;
  // the last 0.1 mm step off a still spell's start comes a little later (0.47 s), and the window
  // (0.2 s) runs from there: about 0.67 s.
  EXPECT_GT(answered_at, 0.5);
  EXPECT_LT(answered_at, 0.9);
  EXPECT_LT(std::abs(left(2.0).p.y() - y_then), 1e-4);  // m: what it moved after the answer
}

TEST(RestMonitor, ATurningToolIsNotAtRest) {
  Bench b;
  b.start();
  b.monitor.call<void>("askAtRest");
  for (int i = 0; i < 1000; ++i) {  // 0.02 rad/s about z: 4 mrad per 0.2 s window, over 2 mrad
    KDL::Frame r = kRight;
    r.M = KDL::Rotation::RotZ(0.02 * i * 1e-3) * r.M;
    b.step(r, kLeft);
  }
  EXPECT_TRUE(b.answers.empty());
  const KDL::Frame stopped(KDL::Rotation::RotZ(0.02) * kRight.M, kRight.p);  // where the turn ended
  for (int i = 0; i < 250; ++i) b.step(stopped, kLeft);
  EXPECT_EQ(b.answers.size(), 1u);
}

TEST(RestMonitor, NoAnswerBeforeBothPosesArrived) {
  Bench b;
  b.start();
  b.monitor.call<void>("askAtRest");
  for (int i = 0; i < 500; ++i) {
    b.right.write(kRight);  // the stick's pose never comes
    b.clock.advance(1ms);
  }
  core::Event e;
  EXPECT_EQ(b.events.read(e), core::FlowStatus::NoData);
}

TEST(RestMonitor, BadPropertiesAreRefusedNamingThem) {
  Bench b;
  b.monitor.setProperty("tolerance", 0.0);
  EXPECT_EQ(b.monitor.configure().message,
            "component 'Rest': property tolerance is 0.000000 m; expected a finite value > 0 m");
  b.monitor.setProperty("tolerance", 1e-4);
  b.monitor.setProperty("angle_tolerance", -1.0);
  EXPECT_EQ(b.monitor.configure().message,
            "component 'Rest': property angle_tolerance is -1.000000 rad; expected a finite value > 0 rad");
  b.monitor.setProperty("angle_tolerance", 2e-3);
  b.monitor.setProperty("window", std::nan(""));
  EXPECT_EQ(b.monitor.configure().message, "component 'Rest': property window is nan s; expected a finite value > 0 s");
}

TEST(RestMonitor, SteppingAndAnsweringAllocateNothing) {
  Bench b;
  b.start();
  for (int i = 0; i < 300; ++i) b.step(kRight, kLeft);
  b.monitor.call<void>("askAtRest");
  const long calls = test_support::allocationsDuring([&] {
    for (int i = 0; i < 250; ++i) {  // the answer comes in the 200th
      b.right.write(kRight);
      b.left.write(kLeft);
      b.clock.advance(1ms);
    }
  });
  EXPECT_EQ(calls, 0);
  core::Event e;
  ASSERT_EQ(b.events.read(e), core::FlowStatus::NewData);
  EXPECT_EQ(e.name.str(), "e_at_rest");
}

}  // namespace
}  // namespace cobra::components::test
