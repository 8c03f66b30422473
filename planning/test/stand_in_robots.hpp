#pragma once
// Stand-in robots for the planning tests only: NOT the I-SUR or UR5 models (those come from the
// kinematics library). Each has a closed-form "IK" so that the expected result of every test is
// known by construction.

#include <cmath>
#include <span>

#include <kdl/frames.hpp>

#include "cobra/planning/robot_model.hpp"

namespace cobra::planning::test {

/// A free-flying tool: its only link is the tool itself; reachable inside a sphere.
class StandInFreeFlyer final : public RobotModel {
 public:
  StandInFreeFlyer(KDL::Vector centre, double reach) : centre_(centre), reach_(reach) {}
  std::size_t toolCount() const override { return 1; }
  std::size_t linkCount() const override { return 1; }
  Reachability solve(std::span<const KDL::Frame> tools, std::span<KDL::Frame> links) override {
    if ((tools[0].p - centre_).Norm() > reach_) return Reachability::Unreachable;
    links[0] = tools[0];
    return Reachability::Reachable;
  }

 private:
  KDL::Vector centre_;
  double reach_;
};

/// A gantry (three prismatic joints x, y, z plus a spherical wrist): link 0 is the carriage
/// `column_offset` above the tool position with the base's orientation (a vertical column hangs
/// from it in the scenes), link 1 the tool. Reachable when |x|, |y| <= half_span and
/// z in [z_min, z_max] (base frame, m).
class StandInGantry final : public RobotModel {
 public:
  StandInGantry(double half_span, double z_min, double z_max, double column_offset)
      : half_span_(half_span), z_min_(z_min), z_max_(z_max), column_offset_(column_offset) {}
  std::size_t toolCount() const override { return 1; }
  std::size_t linkCount() const override { return 2; }
  Reachability solve(std::span<const KDL::Frame> tools, std::span<KDL::Frame> links) override {
    const KDL::Vector& p = tools[0].p;
    if (std::abs(p.x()) > half_span_ || std::abs(p.y()) > half_span_ || p.z() < z_min_ || p.z() > z_max_)
      return Reachability::Unreachable;
    links[0] = KDL::Frame(KDL::Vector(p.x(), p.y(), p.z() + column_offset_));
    links[1] = tools[0];
    return Reachability::Reachable;
  }

 private:
  double half_span_, z_min_, z_max_, column_offset_;
};

/// One solver for both tools (thesis Algorithm 5.1): two free flyers on one base, unreachable
/// when the tools are farther apart than `max_separation` (m). Links: tool 0, tool 1.
class StandInTwoArmed final : public RobotModel {
 public:
  explicit StandInTwoArmed(double max_separation) : max_separation_(max_separation) {}
  std::size_t toolCount() const override { return 2; }
  std::size_t linkCount() const override { return 2; }
  Reachability solve(std::span<const KDL::Frame> tools, std::span<KDL::Frame> links) override {
    if ((tools[0].p - tools[1].p).Norm() > max_separation_) return Reachability::Unreachable;
    links[0] = tools[0];
    links[1] = tools[1];
    return Reachability::Reachable;
  }

 private:
  double max_separation_;
};

}  // namespace cobra::planning::test
