// StitchPlanner: the plan's count and places on a 40 mm cut, targets on the simulated wound's own
// edge points (straight and curved cuts), the plan following the wound as a pulled stitch narrows
// its neighbours, places a neighbour closed skipped, and the error messages for bad edges.

#include "cobra/suturing/stitch_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cobra/sim/wound.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::Wound;
using cobra::sim::WoundModel;
using cobra::sim::WoundSide;
using cobra::suturing::StitchPlanner;
using cobra::suturing::StitchTarget;
using cobra::suturing::WoundEdges;
using cobra::test_support::messageOf;

/// What a sensing module would see: both edges sampled every `step` m along the cut.
WoundEdges sense(const Wound& wound, double step = 2e-4) {
  WoundEdges edges;
  const int n = static_cast<int>(std::ceil(wound.length() / step));
  for (int i = 0; i <= n; ++i) {
    const double s = wound.length() * i / n;
    edges.right.push_back(wound.edgePoint(WoundSide::Right, s, 0.0));
    edges.left.push_back(wound.edgePoint(WoundSide::Left, s, 0.0));
  }
  return edges;
}

/// Applies both halves of `t` on the wound and pulls the thread until the stitch is closed.
void stitchAndPull(Wound& wound, const StitchTarget& t) {
  ASSERT_TRUE(wound.actuate(WoundSide::Right, t.right.p).applied());
  ASSERT_TRUE(wound.actuate(WoundSide::Left, t.left.p).applied());
  const int last = static_cast<int>(wound.stitches().size()) - 1;
  for (double lift = 0.0; lift < 0.1 && wound.stitchGap(last) >= wound.model().closed_gap; lift += 1e-4)
    wound.step(t.left.p + KDL::Vector(0.0, 0.0, lift), KDL::Vector(1.0, 1.0, 1.0));
  wound.step(t.left.p, KDL::Vector(1.0, 1.0, 1.0));
}

TEST(StitchPlan, AFortyMillimetreCutTakesFourStitchesOnTheWoundsEdgePoints) {
  const Wound wound(WoundModel{});
  const WoundEdges edges = sense(wound);
  StitchPlanner::check(edges);
  const StitchPlanner planner;
  EXPECT_NEAR(StitchPlanner::length(edges), 0.04, 1e-12);
  ASSERT_EQ(planner.count(edges), 4);
  for (int k = 0; k < 4; ++k) {
    StitchTarget t;
    ASSERT_TRUE(planner.next(edges, k, t));
    EXPECT_EQ(t.index, k);
    EXPECT_NEAR(t.s, 0.008 * (k + 1), 1e-12);
    // The sampled edge is a chord of the elliptic opening: within 1e-6 m of the model's point.
    EXPECT_NEAR((t.right.p - wound.stitchPoint(WoundSide::Right, t.s)).Norm(), 0.0, 1e-6) << k;
    EXPECT_NEAR((t.left.p - wound.stitchPoint(WoundSide::Left, t.s)).Norm(), 0.0, 1e-6) << k;
    EXPECT_NEAR(t.gap, wound.gap(t.s), 1e-6);
    EXPECT_NEAR(t.right.M.UnitX().x(), 1.0, 1e-12);  // along the cut
    EXPECT_NEAR(t.right.M.UnitY().y(), 1.0, 1e-12);  // towards the left edge
  }
  StitchTarget t;
  EXPECT_FALSE(planner.next(edges, 4, t));
}

TEST(StitchPlan, OnACurvedCutEachTargetFacesAcrossTheCut) {
  WoundModel model;
  model.cut.clear();
  constexpr double r = 0.03;
  for (int i = 0; i <= 32; ++i) {  // a quarter circle, counter-clockwise
    const double a = 0.5 * std::numbers::pi * i / 32;
    model.cut.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
  }
  const Wound wound(model);
  const WoundEdges edges = sense(wound);
  const StitchPlanner planner;
  ASSERT_EQ(planner.count(edges), 4);  // 47 mm: 8, 16, 24, 32 mm (40 mm would be 7 mm from the end)
  for (int k = 0; k < 4; ++k) {
    StitchTarget t;
    ASSERT_TRUE(planner.next(edges, k, t));
    // The centreline of the sampled edges runs 0.1 mm shorter than the cut's polyline at most.
    EXPECT_NEAR((t.right.p - wound.stitchPoint(WoundSide::Right, t.s)).Norm(), 0.0, 1e-4) << k;
    const KDL::Vector across = t.left.p - t.right.p;
    EXPECT_NEAR(KDL::dot(across / across.Norm(), t.right.M.UnitY()), 1.0, 1e-6) << k;
    EXPECT_NEAR(KDL::dot(t.right.M.UnitY(), wound.normal(t.s)), 1.0, 2e-3) << k;
  }
}

TEST(StitchPlan, ThePlanFollowsTheWoundAsItCloses) {
  Wound wound(WoundModel{});
  const StitchPlanner planner;
  StitchTarget first, second_before, second_after;
  ASSERT_TRUE(planner.next(sense(wound), 0, first));
  ASSERT_TRUE(planner.next(sense(wound), 1, second_before));
  stitchAndPull(wound, first);
  ASSERT_TRUE(planner.next(sense(wound), 1, second_after));
  EXPECT_EQ(second_after.index, 1);
  // The first stitch's pull narrowed its neighbour: the edges there moved towards each other.
  EXPECT_LT(second_after.gap, second_before.gap - 1e-4);
  EXPECT_LT((second_after.right.p - wound.stitchPoint(WoundSide::Right, second_after.s)).Norm(), 1e-6);
  EXPECT_GT((second_after.right.p - second_before.right.p).Norm(), 5e-5);
}

TEST(StitchPlan, APlaceANeighbourClosedIsSkipped) {
  WoundEdges edges = sense(Wound(WoundModel{}));
  for (std::size_t i = 0; i < edges.right.size(); ++i) {  // close the cut around 16 mm
    const double s = 0.04 * static_cast<double>(i) / static_cast<double>(edges.right.size() - 1);
    if (std::abs(s - 0.016) < 0.002) edges.left[i] = edges.right[i] = (edges.left[i] + edges.right[i]) * 0.5;
  }
  StitchTarget t;
  ASSERT_TRUE(StitchPlanner().next(edges, 1, t));
  EXPECT_EQ(t.index, 2);
}

TEST(StitchPlan, BadEdgesAndParametersAreRefusedWithWhatWasExpected) {
  WoundEdges edges = sense(Wound(WoundModel{}));
  edges.left.pop_back();
  EXPECT_EQ(messageOf([&] { StitchPlanner::check(edges); }),
            "wound edges: 201 right and 200 left points: expected as many of each, facing each other across the cut");
  StitchTarget t;
  EXPECT_FALSE(StitchPlanner().next(edges, 0, t));  // no stitch from bad edges, no exception
  edges = WoundEdges{{KDL::Vector::Zero()}, {KDL::Vector(0, 0.01, 0)}};
  EXPECT_EQ(messageOf([&] { StitchPlanner::check(edges); }),
            "wound edges: 1 point(s) per edge: expected at least 2 along the cut");
  edges = sense(Wound(WoundModel{}));
  edges.skin_normal = KDL::Vector(0, 0, 2);
  EXPECT_EQ(messageOf([&] { StitchPlanner::check(edges); }),
            "wound edges: the skin normal has length 2: expected a unit vector out of the skin");
  cobra::suturing::StitchPlanModel model;
  model.spacing = 0.0;
  EXPECT_EQ(messageOf([&] { StitchPlanner p(model); }), "stitch plan: spacing is 0 m: expected a finite value > 0 m");
}

}  // namespace
