// Seeded random feasible queries (planning/test/random_queries.hpp: the first of the queries
// bench/planning_bench.cpp's RandomQueries* draw, with the deployments' planner settings) on the
// puncturing and the suturing scene: the success rate, and every returned path followed as the
// robots' controllers follow it, checked independently of the planner's own verifier: the
// Cartesian interpolation stepped at the trajectory generator's speed through
// kinematics::ContinuousIk / ContinuousIsurSuturingIk (the solvers and the continuity rule the
// simulated robots use, built here from cobra::kinematics, not the planner's robot models), every
// step accepted (no branch change, every joint within its velocity limit over the step), and every
// tracked state collision-free (StateValidator::checkJoints: forward kinematics and FCL).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <kdl/jntarray.hpp>

#include "cobra/kinematics/continuity.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/isur_continuity.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "joint_path_checks.hpp"
#include "random_queries.hpp"

namespace cobra::planning {
namespace {

using test::Query;
using test::RandomScene;

/// Period of the controllers' continuity rule here [s]: the simulated robots step at 1 ms; 10 ms
/// steps along the same trajectory bound the same joint velocities (max_velocity · dt) with a
/// tenth of the work.
constexpr double kPeriod = 0.01;

/// How long the Cartesian trajectory generator takes over segment a → b [s] (its speeds in `o`).
double generatorDuration(const PlannerOptions& o, const DualPose& a, const DualPose& b) {
  double duration = o.blend_time;
  for (const auto& [from, to] : {std::pair{&a.first, &b.first}, std::pair{&a.second, &b.second}}) {
    for (int i = 0; i < 3; ++i) duration = std::max(duration, std::abs(to->p(i) - from->p(i)) / o.max_linear_velocity);
    KDL::Vector axis;
    duration = std::max(duration, (from->M.Inverse() * to->M).GetRotAngle(axis) / o.max_angular_velocity);
  }
  return duration;
}

/// The controllers of a scene's robots: one continuity-keeping IK per robot, fed the tool poses
/// of q in its base frame and model tool frame.
class Controllers {
 public:
  explicit Controllers(StateValidator& validator) : validator_(validator) {
    for (const RobotPlacement& robot : validator.scene().robots) {
      if (robot.name == "ur5") {
        auto solver = std::make_unique<kinematics::Ur5Solver>(kinematics::Ur5Parameters{}, kinematics::Ur5Solver::defaultLimits(),
                                                              KDL::Frame::Identity(), Ur5Model::defaultProbe());
        single_.push_back(std::make_unique<kinematics::ContinuousIk>(
            *solver, std::vector<double>(6, Ur5Model::kMaxJointVelocity), kPeriod));
        solvers_.push_back(std::move(solver));
      } else if (robot.tool_indices.size() == 1) {
        auto solver = std::make_unique<kinematics::IsurPuncturingSolver>();
        std::vector<double> velocity(8, IsurPuncturingModel::kMaxRevoluteVelocity);
        std::fill_n(velocity.begin(), 3, IsurPuncturingModel::kMaxSliderVelocity);
        single_.push_back(std::make_unique<kinematics::ContinuousIk>(*solver, velocity, kPeriod));
        solvers_.push_back(std::move(solver));
      } else {
        suturing_ = std::make_unique<kinematics::IsurSuturingSolver>();
        std::vector<double> velocity(14, IsurPuncturingModel::kMaxRevoluteVelocity);
        std::fill_n(velocity.begin(), 3, IsurPuncturingModel::kMaxSliderVelocity);
        two_tools_ = std::make_unique<kinematics::ContinuousIsurSuturingIk>(*suturing_, velocity, kPeriod);
        single_.push_back(nullptr);
      }
    }
  }

  /// One control step to the tool poses `tools` from joints `q` (updated): false with `why`
  /// when a robot's continuity-keeping IK refuses it.
  bool step(const DualPose& tools, JointState& q, std::string& why) {
    const SceneDescription& scene = validator_.scene();
    for (std::size_t r = 0; r < scene.robots.size(); ++r) {
      const RobotPlacement& robot = scene.robots[r];
      const std::size_t offset = validator_.jointOffset(r), n = validator_.model(r).jointCount();
      KDL::Frame targets[2];
      for (std::size_t t = 0; t < robot.tool_indices.size(); ++t)
        targets[t] = robot.base_in_world.Inverse() * (robot.tool_indices[t] == 0 ? tools.first : tools.second) *
                     robot.toolFrame(t).Inverse();
      KDL::JntArray current(static_cast<unsigned>(n)), next(static_cast<unsigned>(n));
      for (std::size_t j = 0; j < n; ++j) current(static_cast<unsigned>(j)) = q[offset + j];
      const kinematics::IkStatus status = single_[r] ? single_[r]->solve(targets[0], current, next)
                                                     : two_tools_->solve(targets[0], targets[1], current, next);
      if (status != kinematics::IkStatus::Ok) {
        why = "robot '" + robot.name + "': " + std::string(kinematics::toString(status));
        return false;
      }
      for (std::size_t j = 0; j < n; ++j) q[offset + j] = next(static_cast<unsigned>(j));
    }
    return true;
  }

 private:
  StateValidator& validator_;
  std::vector<std::unique_ptr<kinematics::KinematicsSolver>> solvers_;
  std::vector<std::unique_ptr<kinematics::ContinuousIk>> single_;
  std::unique_ptr<kinematics::IsurSuturingSolver> suturing_;
  std::unique_ptr<kinematics::ContinuousIsurSuturingIk> two_tools_;
};

/// The controllers follow the solved path from the query's start at the generator's speeds: every
/// step accepted, and every tracked state collision-free with at least half the scene's clearance
/// (the planner keeps the whole clearance at its verification's points, verify_points_per_segment
/// per segment; between them a state may come a little closer).
void expectControllersFollow(StateValidator& validator, const PlannerOptions& o, const PlanResult& result,
                             const JointState& start, std::size_t query) {
  Controllers controllers(validator);
  const double clearance = 0.5 * validator.scene().min_collision_distance;
  JointState q = start;
  std::string why;
  for (std::size_t k = 0; k + 1 < result.waypoints.size(); ++k) {
    const DualPose& a = result.waypoints[k];
    const DualPose& b = result.waypoints[k + 1];
    const auto steps = static_cast<std::size_t>(std::ceil(generatorDuration(o, a, b) / kPeriod));
    for (std::size_t i = 1; i <= steps; ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(steps);
      ASSERT_TRUE(controllers.step({interpolate(a.first, b.first, s), interpolate(a.second, b.second, s)}, q, why))
          << "query " << query << ", segment " << k << " at " << s << ": " << why;
      const ValidityResult state = validator.checkJoints(q, true);
      ASSERT_TRUE(state.valid() || (state.validity == Validity::TooClose && state.distance >= clearance))
          << "query " << query << ", segment " << k << " at " << s << ": " << describe(state);
    }
  }
}

/// Plans the first `count` queries of `setup` (the bench's, its work limit and speeds); every
/// solved path is cross-checked. Returns the number solved.
std::size_t planAndCrossCheck(const RandomScene& setup, std::size_t count) {
  SceneDescription scene = setup.scene();
  RobotModels models = makeRobotModels(scene);
  StateValidator validator(std::move(scene), std::move(models));
  std::map<std::string, int> dropped;
  const std::vector<Query> queries = test::randomQueries(validator, setup, count, dropped);
  std::size_t solved = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    PlannerOptions o = setup.options;
    o.seed = static_cast<std::uint32_t>(i + 1);
    o.max_linear_velocity = queries[i].max_linear_velocity;
    o.max_angular_velocity = queries[i].max_angular_velocity;
    MotionPlanner planner(validator, o);
    const PlanResult result = planner.planPath(queries[i].start, queries[i].goal);
    if (!result.solved()) {
      std::printf("query %zu: %s\n", i, result.message.c_str());
      continue;
    }
    ++solved;
    EXPECT_TRUE(KDL::Equal(result.waypoints.back().first, queries[i].goal.first, 1e-9)) << "query " << i;
    EXPECT_TRUE(KDL::Equal(result.waypoints.back().second, queries[i].goal.second, 1e-9)) << "query " << i;
    expectControllersFollow(validator, o, result, queries[i].start, i);
  }
  return solved;
}

// The target is 99 % (all 50); measured, 48 of the 50 (the bench: 979 of its 1,000 queries): the
// two others find no path within the 10,000-check work limit. The floor makes a regression fail.
TEST(RandomQueries, PuncturingQueriesAreSolvedAndTheControllersFollowEveryPath) {
  EXPECT_GE(planAndCrossCheck(test::puncturingRandom("RRTConnect"), 50), 48u);
}

// The suturing scene's queries are harder (the tips kept inside the deployment's 25 cm box over
// the phantom, the 20,000-check work limit): measured, 12 of the first 20 are solved (the bench:
// see planning/README.md), the floor; every solved path is followed by the robot's controller.
TEST(RandomQueries, SuturingPathsAreFollowedByTheTwoArmedRobotsController) {
  EXPECT_GE(planAndCrossCheck(test::suturingRandom("RRTConnect"), 20), 12u);
}

}  // namespace
}  // namespace cobra::planning
