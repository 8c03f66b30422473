// Wound: the cut's geometry (straight and curved), half-stitches accepted only at the edge point
// inside the wound and in order, the thread's tension closing a pulled stitch at the stated
// equilibrium and then breaking, the stick hooking the thread, four stitches closing a 40 mm
// cut at each stitch, the models' error messages, and no allocation on the stepping calls.

#include "cobra/sim/wound.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::StitchMiss;
using cobra::sim::ThreadModel;
using cobra::sim::Wound;
using cobra::sim::WoundModel;
using cobra::sim::WoundSide;
using cobra::test_support::messageOf;

constexpr double kTol = 1e-12;

/// A quarter circle of radius r (m) on the skin, as a polyline of n segments.
WoundModel curvedCut(double r, int n) {
  WoundModel m;
  m.cut.clear();
  for (int i = 0; i <= n; ++i) {
    const double a = 0.5 * std::numbers::pi * i / n;
    m.cut.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
  }
  return m;
}

/// Pulls the tool straight up from `from` in 0.1 mm steps until `done` or `max_lift` m.
template <class Done>
void pullUp(Wound& wound, const KDL::Vector& from, double max_lift, Done done) {
  for (double lift = 0.0; lift <= max_lift && !done(); lift += 1e-4)
    wound.step(from + KDL::Vector(0.0, 0.0, lift), KDL::Vector(1.0, 1.0, 1.0));
}

TEST(Wound, AStraightCutOpensEllipticallyWithItsLeftEdgeAlongTheNormal) {
  const Wound wound(WoundModel{});
  EXPECT_NEAR(wound.length(), 0.04, kTol);
  EXPECT_NEAR(wound.initialGap(0.02), 0.006, kTol);
  EXPECT_NEAR(wound.initialGap(0.0), 0.0, kTol);
  EXPECT_NEAR(wound.initialGap(0.01), 0.006 * std::sqrt(0.75), kTol);  // u = -0.5
  EXPECT_NEAR(wound.normal(0.01).y(), 1.0, kTol);                        // z × x = y: left is +y
  const KDL::Vector left = wound.edgePoint(WoundSide::Left, 0.02, 0.002);
  const KDL::Vector right = wound.edgePoint(WoundSide::Right, 0.02, 0.002);
  EXPECT_NEAR(left.y(), 0.003, kTol);
  EXPECT_NEAR(right.y(), -0.003, kTol);
  EXPECT_NEAR(left.z(), -0.002, kTol);
  EXPECT_NEAR(left.x(), 0.0, kTol);
}

TEST(Wound, ACurvedCutsEdgesLieAcrossItsCentrelineAtHalfTheGap) {
  constexpr double r = 0.03;
  const Wound wound(curvedCut(r, 32));
  EXPECT_NEAR(wound.length(), 0.5 * std::numbers::pi * r, 1e-5);  // the polyline's chord deficit
  std::mt19937 random(7);
  std::uniform_real_distribution<double> along(0.0, wound.length());
  for (int i = 0; i < 100; ++i) {  // 100 seeded points along the cut
    const double s = along(random);
    const KDL::Vector c = wound.centre(s);
    EXPECT_NEAR(wound.nearestS(c), s, 1e-9);
    const KDL::Vector n = wound.normal(s);
    EXPECT_NEAR(n.Norm(), 1.0, kTol);
    EXPECT_NEAR(KDL::dot(n, c / c.Norm()), -1.0, 2e-3);  // across the arc, inwards (left of a counter-clockwise cut), within half a segment's turn
    const KDL::Vector across = wound.edgePoint(WoundSide::Left, s, 0.0) - wound.edgePoint(WoundSide::Right, s, 0.0);
    EXPECT_NEAR(across.Norm(), wound.gap(s), kTol);
  }
}

TEST(Wound, AHalfStitchNeedsTheTipAtTheEdgePointInsideTheWound) {
  Wound wound(WoundModel{});
  const double s = 0.02;
  const KDL::Vector right = wound.stitchPoint(WoundSide::Right, s);

  auto r = wound.actuate(WoundSide::Left, wound.stitchPoint(WoundSide::Left, s));
  EXPECT_EQ(r.miss, StitchMiss::LeftBeforeRight);
  r = wound.actuate(WoundSide::Right, right + KDL::Vector(0.0, 0.0, 0.003));  // 1 mm above the skin
  EXPECT_EQ(r.miss, StitchMiss::OutsideWound);
  r = wound.actuate(WoundSide::Right, right + KDL::Vector(0.0, 0.0025, 0.0));  // inside, 2.5 mm off the edge
  EXPECT_EQ(r.miss, StitchMiss::FarFromEdge);
  EXPECT_NEAR(r.distance, 0.0025, 1e-12);
  EXPECT_TRUE(wound.stitches().empty());

  r = wound.actuate(WoundSide::Right, right + KDL::Vector(0.0005, 0.0005, 0.0));  // within 1.5 mm
  ASSERT_TRUE(r.applied()) << toString(r.miss);
  EXPECT_EQ(r.stitch, 0);
  r = wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.01));
  EXPECT_EQ(r.miss, StitchMiss::RightStillOpen);
  r = wound.actuate(WoundSide::Left, wound.stitchPoint(WoundSide::Left, 0.017));  // 3 mm along the cut
  EXPECT_EQ(r.miss, StitchMiss::NotAtOpenStitch);
  r = wound.actuate(WoundSide::Left, wound.stitchPoint(WoundSide::Left, s));
  ASSERT_TRUE(r.applied()) << toString(r.miss);
  ASSERT_EQ(wound.stitches().size(), 1u);
  EXPECT_TRUE(wound.stitches()[0].complete());
  EXPECT_NEAR(wound.stitches()[0].s, s + 0.0005, 1e-9);  // where the right half went in
}

TEST(Wound, PullingAStitchClosesItAtTheTissuesEquilibriumThenTheThreadBreaks) {
  WoundModel model;
  ThreadModel thread;
  Wound wound(model, thread);
  const double s = 0.02;
  ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, s)).applied());
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, s);
  ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied());

  // Within the slack: no tension, no closure.
  wound.step(tip + KDL::Vector(0.0, 0.0, 0.5 * thread.slack), KDL::Vector(1.0, 1.0, 1.0));
  EXPECT_EQ(wound.tension(), 0.0);
  EXPECT_EQ(wound.stitches()[0].closure, 0.0);

  // Taut: the tension the thread carries is what the tissue resists, T = k_t·δ (the crossing
  // shortens one for one with δ; the neighbours' skin points move a little: 2 %).
  pullUp(wound, tip, 0.1, [&] { return wound.tension() > 0.5; });
  const double first = wound.tension();
  ASSERT_GT(first, 0.5);
  EXPECT_NEAR(first, model.tissue_stiffness * wound.stitches()[0].closure, 0.02 * first);
  EXPECT_LT(wound.stitchGap(0), model.max_gap);

  // Pulled until closed, then the thread alone stretches until it breaks.
  pullUp(wound, tip, 0.2, [&] { return wound.stitchGap(0) < model.closed_gap; });
  EXPECT_LT(wound.stitchGap(0), model.closed_gap);
  EXPECT_NEAR(wound.tension(), model.tissue_stiffness * wound.stitches()[0].closure, 0.02 * wound.tension());
  double highest = 0.0;
  pullUp(wound, tip, 0.2, [&] {
    highest = std::max(highest, wound.tension());
    return wound.broken();
  });
  EXPECT_TRUE(wound.broken());
  EXPECT_LE(highest, thread.breaking_tension);
  EXPECT_GT(highest, thread.breaking_tension - thread.stiffness * 1e-4 - 1e-9);  // the last 0.1 mm step
  EXPECT_EQ(wound.tension(), 0.0);
  EXPECT_EQ(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.03)).miss, StitchMiss::ThreadBroken);
}

TEST(Wound, APulledStitchKeepsItsClosureWhenTheThreadSlackens) {
  Wound wound(WoundModel{});
  ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.02)).applied());
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, 0.02);
  ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied());
  pullUp(wound, tip, 0.1, [&] { return wound.tension() > 1.0; });
  const double closure = wound.stitches()[0].closure;
  ASSERT_GT(closure, 0.0);
  wound.step(tip, KDL::Vector(1.0, 1.0, 1.0));
  EXPECT_EQ(wound.tension(), 0.0);
  EXPECT_EQ(wound.stitches()[0].closure, closure);
  // The closure narrows the gap around the stitch, fading over closure_spread.
  const double spread = WoundModel{}.closure_spread;
  EXPECT_LT(wound.gap(0.02 + 0.5 * spread), wound.initialGap(0.02 + 0.5 * spread));
  EXPECT_NEAR(wound.gap(0.02 + spread), wound.initialGap(0.02 + spread), kTol);
}

TEST(Wound, TheStickHooksTheFreeThreadAndPushesItAside) {
  Wound wound(WoundModel{});
  ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.02)).applied());
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, 0.02);
  ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied());
  const KDL::Vector tool = tip + KDL::Vector(0.0, 0.0, 0.015);  // within the slack: no tension yet
  const KDL::Vector exit = wound.edgePoint(WoundSide::Left, 0.02, 0.0) + KDL::Vector(0.0, WoundModel{}.bite, 0.0);
  const KDL::Vector middle = (exit + tool) * 0.5;

  wound.step(tool, middle + KDL::Vector(0.005, 0.0, 0.0));  // 5 mm beside the thread: not caught
  EXPECT_FALSE(wound.hooked());
  EXPECT_NEAR(wound.freeThreadDistance(middle + KDL::Vector(0.005, 0.0, 0.0)), 0.005, 1e-9);
  wound.step(tool, middle + KDL::Vector(0.0015, 0.0, 0.0));
  ASSERT_TRUE(wound.hooked());
  const double straight = wound.threadPath();
  // Caught where it touched the stick's side, 1.5 mm from its tip: still straight, no pull yet.
  EXPECT_NEAR((wound.hookPoint() - middle).Norm(), 0.0, kTol);
  EXPECT_NEAR(wound.threadPath(), straight, kTol);
  const KDL::Vector aside = middle - KDL::Vector(0.015, 0.0, 0.0);  // the tip pushed 15 mm along the cut
  wound.step(tool, aside + KDL::Vector(0.0015, 0.0, 0.0));
  EXPECT_GT(wound.threadPath(), straight);
  EXPECT_NEAR((wound.hookPoint() - aside).Norm(), 0.0, kTol);  // the touching point moved with it
  EXPECT_NEAR(wound.freeThreadDistance(aside), 0.0, kTol);   // it bends round the stick
  EXPECT_GT(wound.freeThreadDistance(middle), 0.005);        // and left the place it hung
  wound.releaseThread();
  EXPECT_FALSE(wound.hooked());
}

TEST(Wound, TheRevisionChangesWithTheWoundsStateNotWithTheTension) {
  Wound wound(WoundModel{});
  const KDL::Vector far(1.0, 1.0, 1.0);
  std::uint64_t seen = wound.revision();
  const auto changed = [&] {
    const bool moved = wound.revision() != seen;
    seen = wound.revision();
    return moved;
  };
  EXPECT_EQ(wound.sideAt(wound.stitchPoint(WoundSide::Right, 0.01)), WoundSide::Right);
  EXPECT_EQ(wound.sideAt(wound.stitchPoint(WoundSide::Left, 0.01)), WoundSide::Left);
  EXPECT_FALSE(wound.actuate(WoundSide::Right, KDL::Vector(0.0, 0.0, 0.01)).applied());
  EXPECT_FALSE(changed());  // a miss changes nothing
  ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.02)).applied());
  EXPECT_TRUE(changed());
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, 0.02);
  ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied());
  EXPECT_TRUE(changed());
  wound.step(tip + KDL::Vector(0.0, 0.0, 0.005), far);  // within the slack: the tension alone moves
  EXPECT_FALSE(changed());
  pullUp(wound, tip, 0.1, [&] { return wound.stitches()[0].closure > 0.0; });
  EXPECT_TRUE(changed());  // the closure moved the edges
  const KDL::Vector exit = wound.edgePoint(WoundSide::Left, 0.02, 0.0) + KDL::Vector(0.0, WoundModel{}.bite, 0.0);
  const KDL::Vector tool = tip + KDL::Vector(0.0, 0.0, 0.002);
  wound.step(tool, far);
  changed();
  wound.step(tool, (exit + tool) * 0.5);
  ASSERT_TRUE(wound.hooked());
  EXPECT_TRUE(changed());
  wound.releaseThread();
  EXPECT_TRUE(changed());
  wound.releaseThread();
  EXPECT_FALSE(changed());  // already free
}

TEST(Wound, TheTensedThreadPullsTheToolTowardItsHookAndTheStickBothWays) {
  Wound wound(WoundModel{});
  EXPECT_EQ(wound.toolForce(), KDL::Vector::Zero());  // no stitch
  ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.02)).applied());
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, 0.02);
  ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied());
  const KDL::Vector far(1.0, 1.0, 1.0);
  wound.step(tip + KDL::Vector(0.0, 0.0, 0.005), far);
  EXPECT_EQ(wound.toolForce(), KDL::Vector::Zero());  // slack
  const KDL::Vector exit = wound.edgePoint(WoundSide::Left, 0.02, 0.0) + KDL::Vector(0.0, WoundModel{}.bite, 0.0);
  KDL::Vector tool = tip + KDL::Vector(0.0, 0.0, 0.015);
  const KDL::Vector stick = (exit + tool) * 0.5 - KDL::Vector(0.012, 0.0, 0.0);  // hooks, pushed 12 mm aside
  wound.step(tool, (exit + tool) * 0.5);
  ASSERT_TRUE(wound.hooked());
  for (int i = 0; i < 400 && wound.tension() < 2.0; ++i) {  // the tool up 0.1 mm a step, the stick holding
    tool += KDL::Vector(0.0, 0.0, 1e-4);
    wound.step(tool, stick);
  }
  ASSERT_GT(wound.tension(), 2.0);
  const KDL::Vector last = wound.edgePoint(WoundSide::Left, 0.02, 0.0) +
                           wound.normal(0.02) * WoundModel{}.bite;  // the left skin point
  const KDL::Vector to_hook = (stick - tool) / (stick - tool).Norm();
  EXPECT_NEAR((wound.toolForce() - to_hook * wound.tension()).Norm(), 0.0, 1e-9);
  const KDL::Vector expected = ((last - stick) / (last - stick).Norm() + (tool - stick) / (tool - stick).Norm()) *
                               wound.tension();
  EXPECT_NEAR((wound.stickForce() - expected).Norm(), 0.0, 1e-9);
  wound.releaseThread();
  EXPECT_EQ(wound.stickForce(), KDL::Vector::Zero());
}

TEST(Wound, ReleasedOverATimeTheThreadsPullOnTheStickFadesToNothing) {
  ThreadModel thread;
  thread.release_time = 0.2;
  Wound wound(WoundModel{}, thread);
  ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.02)).applied());
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, 0.02);
  ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied());
  const KDL::Vector exit = wound.edgePoint(WoundSide::Left, 0.02, 0.0) + KDL::Vector(0.0, WoundModel{}.bite, 0.0);
  KDL::Vector tool = tip + KDL::Vector(0.0, 0.0, 0.015);
  wound.step(tool, (exit + tool) * 0.5, 1e-3);
  ASSERT_TRUE(wound.hooked());
  const KDL::Vector stick = (exit + tool) * 0.5 - KDL::Vector(0.012, 0.0, 0.0);  // pushed 12 mm aside
  for (int i = 0; i < 400 && wound.tension() < 2.0; ++i) {
    tool += KDL::Vector(0.0, 0.0, 1e-4);
    wound.step(tool, stick, 1e-3);
  }
  const double held = wound.stickForce().Norm();
  ASSERT_GT(held, 1.0);
  wound.releaseThread();
  double previous = held;
  int steps = 0;
  for (; wound.hooked() && steps < 1000; ++steps) {  // 1 ms steps, the stick and the tool holding
    wound.step(tool, stick, 1e-3);
    const double pull = wound.stickForce().Norm();
    EXPECT_LE(pull, previous + 1e-12) << steps;  // it only fades
    EXPECT_LT(previous - pull, 0.05 * held) << steps;  // by less than 5 % of it a millisecond
    previous = pull;
  }
  EXPECT_NEAR(steps, 200, 1);  // gone after release_time
  EXPECT_EQ(wound.stickForce(), KDL::Vector::Zero());
  EXPECT_FALSE(wound.releasing());
  // Resting against the thread it let go, the stick does not catch it; come back to it, it does.
  const KDL::Vector touching = (exit + tool) * 0.5 + KDL::Vector(0.001, 0.0, 0.0);
  wound.step(tool, touching, 1e-3);
  EXPECT_FALSE(wound.hooked());
  wound.step(tool, touching + KDL::Vector(0.01, 0.0, 0.0), 1e-3);
  wound.step(tool, touching, 1e-3);
  EXPECT_TRUE(wound.hooked());
}

TEST(Wound, FourPulledStitchesCloseAFortyMillimetreCut) {
  const WoundModel model;
  Wound wound(model);
  for (const double s : {0.008, 0.016, 0.024, 0.032}) {
    ASSERT_TRUE(wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, s)).applied()) << s;
    const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, s);
    ASSERT_TRUE(wound.actuate(WoundSide::Left, tip).applied()) << s;
    const int last = static_cast<int>(wound.stitches().size()) - 1;
    pullUp(wound, tip, 0.1, [&] { return wound.stitchGap(last) < model.closed_gap; });
    EXPECT_LT(wound.stitchGap(last), model.closed_gap) << s;
    EXPECT_FALSE(wound.broken()) << s;
    wound.step(tip, KDL::Vector(1.0, 1.0, 1.0));
    EXPECT_TRUE(wound.stitchesClosed()) << s;
  }
  EXPECT_EQ(wound.stitches().size(), 4u);
  // Between and beyond the stitches the cut stays narrower than it opened (the superposed closures).
  EXPECT_LT(wound.maxGap(), 0.3 * model.max_gap);
}

TEST(Wound, BadModelsAreRefusedWithTheParameterAndTheExpectedRange) {
  WoundModel m;
  m.cut = {KDL::Vector(0, 0, 0)};
  EXPECT_EQ(messageOf([&] { Wound w(m); }),
            "wound: cut has 1 point(s): expected at least 2 points of the centreline on the skin (m)");
  m.cut = {KDL::Vector(0, 0, 0), KDL::Vector(0.02, 0, 0.001)};
  EXPECT_EQ(messageOf([&] { Wound w(m); }),
            "wound: cut point 1 has z = 0.001 m: expected z = 0: the cut lies on the skin, the plane z = 0 of the "
            "wound frame");
  m = WoundModel{};
  m.stitch_depth = 0.01;
  EXPECT_EQ(messageOf([&] { Wound w(m); }), "wound: stitch_depth is 0.01 m: expected a depth inside the tissue, in (0, 0.006) m");
  ThreadModel t;
  t.slack = 0.5;
  EXPECT_EQ(messageOf([&] { Wound w(WoundModel{}, t); }),
            "thread: slack is 0.5 m: expected a finite value >= 0 m and below the thread's length");
  t = ThreadModel{};
  t.breaking_tension = -1.0;
  EXPECT_EQ(messageOf([&] { Wound w(WoundModel{}, t); }), "thread: breaking_tension is -1 N: expected a finite value > 0 N");
  t = ThreadModel{};
  t.release_time = -0.1;
  EXPECT_EQ(messageOf([&] { Wound w(WoundModel{}, t); }), "thread: release_time is -0.1 s: expected a finite value >= 0 s");
}

TEST(Wound, ActuatingAndSteppingAllocateNothing) {
  Wound wound(WoundModel{});
  const KDL::Vector tip = wound.stitchPoint(WoundSide::Left, 0.02);
  const long calls = cobra::test_support::allocationsDuring([&] {
    wound.actuate(WoundSide::Right, wound.stitchPoint(WoundSide::Right, 0.02));
    wound.actuate(WoundSide::Left, tip);
    pullUp(wound, tip, 0.05, [] { return false; });
    wound.step(tip, tip + KDL::Vector(0.0, 0.001, 0.01));
  });
  EXPECT_EQ(calls, 0);
}

}  // namespace
