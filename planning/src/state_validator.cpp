#include "cobra/planning/state_validator.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace cobra::planning {

const char* toString(Validity validity) {
  switch (validity) {
    case Validity::Valid: return "valid";
    case Validity::InvalidInput: return "invalid input";
    case Validity::Unreachable: return "unreachable";
    case Validity::TooClose: return "too close";
  }
  return "unknown";
}

std::string describe(const ValidityResult& result) {
  std::ostringstream text;
  text << toString(result.validity);
  if (result.validity == Validity::Unreachable) text << ": robot '" << result.robot << "' has no IK solution";
  if (result.validity == Validity::InvalidInput) text << ": a pose is not finite or its rotation is not orthonormal";
  if (result.validity == Validity::TooClose)
    text << ": " << result.first_group << "/" << result.second_group << " at " << result.distance << " m ("
         << result.first_object << "/" << result.second_object << ")";
  return text.str();
}

namespace {

bool isFiniteFrame(const KDL::Frame& frame) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(frame.p(i))) return false;
  for (const double value : frame.M.data)
    if (!std::isfinite(value)) return false;
  // Orthonormal: R^T R = I and det R = +1 (a proper rotation), to a tolerance for rounding.
  constexpr double kTolerance = 1e-6;
  const KDL::Rotation product = frame.M.Inverse() * frame.M;
  for (unsigned r = 0; r < 3; ++r)
    for (unsigned c = 0; c < 3; ++c)
      if (std::abs(product(r, c) - (r == c ? 1.0 : 0.0)) > kTolerance) return false;
  const KDL::Vector x = frame.M.UnitX(), y = frame.M.UnitY(), z = frame.M.UnitZ();
  return dot(x * y, z) > 0.0;
}

}  // namespace

bool isFinitePose(const DualPose& q) { return isFiniteFrame(q.first) && isFiniteFrame(q.second); }

StateValidator::StateValidator(SceneDescription scene, RobotModels robots) : world_(std::move(scene)) {
  const SceneDescription& description = world_.scene();
  for (std::size_t r = 0; r < description.robots.size(); ++r) {
    const RobotPlacement& placement = description.robots[r];
    const auto it = robots.find(placement.name);
    if (it == robots.end() || !it->second)
      throw std::invalid_argument("state validator: the scene's robot '" + placement.name +
                                  "' has no robot model: pass one under that name");
    const RobotModel& model = *it->second;
    if (model.toolCount() != placement.tool_indices.size())
      throw std::invalid_argument("state validator: robot '" + placement.name + "' takes " +
                                  std::to_string(model.toolCount()) + " tool(s) but the scene gives it " +
                                  std::to_string(placement.tool_indices.size()) + ": fix its `tools`");
    if (model.linkCount() < world_.linksUsedBy(r))
      throw std::invalid_argument("state validator: the scene attaches objects to link " +
                                  std::to_string(world_.linksUsedBy(r) - 1) + " of robot '" + placement.name +
                                  "' but its model has " + std::to_string(model.linkCount()) + " links");
    models_.push_back(it->second);
    tools_.emplace_back(model.toolCount());
    links_.emplace_back(model.linkCount());
    std::vector<KDL::Frame> frames, inverses;
    for (std::size_t t = 0; t < placement.tool_indices.size(); ++t) {
      frames.push_back(placement.toolFrame(t));
      inverses.push_back(frames.back().Inverse());
    }
    tool_in_model_tool_.push_back(std::move(frames));
    model_tool_in_tool_.push_back(std::move(inverses));
    joint_offsets_.push_back(joint_offsets_.back() + model.jointCount());
    joint_space_ = joint_space_ && model.jointCount() > 0;
    seeds_.emplace_back(model.jointCount());
    placed_joints_.emplace_back(model.jointCount());
    placed_known_.push_back(false);
  }
  findMovingPairs();
}

void StateValidator::findMovingPairs() {
  const SceneDescription& description = world_.scene();
  auto declared = [&](const std::string& a, const std::string& b) {
    for (const auto* contacts : {&description.allowed_contacts, &description.primitive_contacts})
      for (const auto& [first, second] : *contacts)
        if ((first == a && second == b) || (first == b && second == a)) return true;
    return false;
  };
  // The candidate object pairs of each checked group pair, and the range of each one's distance
  // over the robots' seeds and 32 seeded random joint states within the limits (those with forward
  // kinematics): a pair whose distance never changes is static (two objects no joint moves, or a
  // robot's base cylinder turning about its own axis above the table).
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> candidates;
  for (const GroupPair& pair : description.checks) {
    candidates.emplace_back();
    for (std::size_t a = 0; a < description.objects.size(); ++a)
      for (std::size_t b = 0; b < description.objects.size(); ++b)
        if (description.objects[a].group == description.groups[pair.first] &&
            description.objects[b].group == description.groups[pair.second] &&
            !declared(description.objects[a].name, description.objects[b].name))
          candidates.back().emplace_back(a, b);
  }
  // GJK's distances of curved shapes (FCL's default solver) vary by up to about a micrometre with
  // the objects' poses: a pair is static when its distance stays within 10 um.
  constexpr double kStaticTolerance = 1e-5;  // m
  std::vector<std::vector<std::pair<double, double>>> ranges;  // per candidate: lowest, highest [m]
  for (const auto& objects : candidates)
    ranges.emplace_back(objects.size(), std::pair{std::numeric_limits<double>::infinity(), -1.0});
  int sampled = 0;
  if (joint_space_) {
    std::vector<double> q(jointCount()), lower(jointCount()), upper(jointCount()), velocity(jointCount());
    for (std::size_t r = 0; r < models_.size(); ++r) {
      const std::span<double> seed(q.data() + joint_offsets_[r], joint_offsets_[r + 1] - joint_offsets_[r]);
      models_[r]->seedJoints(seed);
      const std::span<double> low(lower.data() + joint_offsets_[r], seed.size()), high(upper.data() + joint_offsets_[r], seed.size());
      // Half a radian (metre) about the seed for a model that declares no limits (RobotModel's
      // default jointLimits leaves the spans as they are).
      for (std::size_t j = 0; j < seed.size(); ++j) low[j] = seed[j] - 0.5, high[j] = seed[j] + 0.5;
      models_[r]->jointLimits(low, high, std::span(velocity.data() + joint_offsets_[r], seed.size()));
      for (std::size_t j = 0; j < seed.size(); ++j)  // unlimited joints: a turn about the seed
        if (!(low[j] < high[j]) || !std::isfinite(high[j] - low[j])) low[j] = seed[j] - 3.2, high[j] = seed[j] + 3.2;
    }
    std::mt19937 rng(1);
    for (int state = 0; state <= 32; ++state) {
      if (state > 0)
        for (std::size_t j = 0; j < q.size(); ++j) q[j] = std::uniform_real_distribution<double>(lower[j], upper[j])(rng);
      if (!placeRobotsAt(q).valid()) continue;
      ++sampled;
      for (std::size_t p = 0; p < candidates.size(); ++p)
        for (std::size_t k = 0; k < candidates[p].size(); ++k) {
          const double d = world_.objectDistance(candidates[p][k].first, candidates[p][k].second);
          ranges[p][k] = {std::min(ranges[p][k].first, d), std::max(ranges[p][k].second, d)};
        }
    }
    std::fill(placed_known_.begin(), placed_known_.end(), false);
  }
  for (std::size_t p = 0; p < candidates.size(); ++p) {
    std::vector<std::pair<std::size_t, std::size_t>> moving;
    for (std::size_t k = 0; k < candidates[p].size(); ++k)
      if (sampled < 2 || ranges[p][k].second - ranges[p][k].first > kStaticTolerance) moving.push_back(candidates[p][k]);
    if (moving.empty()) continue;
    const GroupPair& pair = description.checks[p];
    pair_names_.push_back(description.groups[pair.first] + "/" + description.groups[pair.second]);
    pair_objects_.push_back(std::move(moving));
  }
}

Reachability StateValidator::inverseNear(const DualPose& q, std::span<const double> seed, std::span<double> joints,
                                         std::size_t& failed_robot) {
  return inverse(q, seed, joints, failed_robot, Solve::Near);
}

Reachability StateValidator::inverseGoal(const DualPose& q, std::span<const double> start, std::span<double> joints,
                                         std::size_t& failed_robot) {
  return inverse(q, start, joints, failed_robot, Solve::Goal);
}

Reachability StateValidator::inverseGoalAlternative(const DualPose& q, std::span<const double> start,
                                                    std::span<double> joints, std::size_t& failed_robot) {
  return inverse(q, start, joints, failed_robot, Solve::GoalAlternative);
}

Reachability StateValidator::inverse(const DualPose& q, std::span<const double> seed, std::span<double> joints,
                                     std::size_t& failed_robot, Solve solve) {
  bool alternative = false;
  const SceneDescription& description = world_.scene();
  for (std::size_t r = 0; r < models_.size(); ++r) {
    const RobotPlacement& placement = description.robots[r];
    const KDL::Frame world_in_base = placement.base_in_world.Inverse();
    for (std::size_t t = 0; t < placement.tool_indices.size(); ++t)
      tools_[r][t] = world_in_base * (placement.tool_indices[t] == 0 ? q.first : q.second) * model_tool_in_tool_[r][t];
    const std::size_t n = joint_offsets_[r + 1] - joint_offsets_[r];
    std::span<const double> robot_seed;
    if (seed.empty()) {
      models_[r]->seedJoints(seeds_[r]);
      robot_seed = seeds_[r];
    } else {
      robot_seed = seed.subspan(joint_offsets_[r], n);
    }
    const std::span<double> out = joints.subspan(joint_offsets_[r], n);
    Reachability reached = Reachability::Unreachable;
    if (solve == Solve::GoalAlternative &&
        models_[r]->inverseGoalAlternative(tools_[r], robot_seed, out) == Reachability::Reachable) {
      reached = Reachability::Reachable;
      alternative = true;
    } else {
      reached = solve == Solve::Near ? models_[r]->inverseNear(tools_[r], robot_seed, out)
                                     : models_[r]->inverseGoal(tools_[r], robot_seed, out);
    }
    if (reached != Reachability::Reachable) {
      failed_robot = r;
      return reached;
    }
  }
  if (solve == Solve::GoalAlternative && !alternative) {
    failed_robot = models_.size();
    return Reachability::Unreachable;
  }
  return Reachability::Reachable;
}

ValidityResult StateValidator::placeRobots(const DualPose& q) {
  ValidityResult result;
  if (!isFinitePose(q)) {
    result.validity = Validity::InvalidInput;
    return result;
  }
  const SceneDescription& description = world_.scene();
  for (std::size_t r = 0; r < models_.size(); ++r) {
    const RobotPlacement& placement = description.robots[r];
    const KDL::Frame world_in_base = placement.base_in_world.Inverse();
    for (std::size_t t = 0; t < placement.tool_indices.size(); ++t)
      tools_[r][t] = world_in_base * (placement.tool_indices[t] == 0 ? q.first : q.second) * model_tool_in_tool_[r][t];
    placed_known_[r] = false;  // placed from tool poses now, or left where the failed solve leaves it
    if (models_[r]->solve(tools_[r], links_[r]) != Reachability::Reachable) {
      result.validity = Validity::Unreachable;
      result.robot = placement.name;
      return result;
    }
    for (KDL::Frame& link : links_[r]) link = placement.base_in_world * link;
    world_.setRobotLinks(r, links_[r]);
  }
  return result;
}

ValidityResult StateValidator::placeRobotsAt(std::span<const double> q) {
  ValidityResult result;
  const SceneDescription& description = world_.scene();
  for (std::size_t r = 0; r < models_.size(); ++r) {
    const std::span<const double> joints = q.subspan(joint_offsets_[r], joint_offsets_[r + 1] - joint_offsets_[r]);
    // Bitwise: the same joint values give the same link frames (-0.0 and 0.0 differ, and are moved).
    if (placed_known_[r] &&
        std::memcmp(joints.data(), placed_joints_[r].data(), joints.size() * sizeof(double)) == 0)
      continue;
    if (!models_[r]->linkFramesAt(joints, links_[r])) {
      result.validity = Validity::Unreachable;
      result.robot = description.robots[r].name;
      return result;
    }
    for (KDL::Frame& link : links_[r]) link = description.robots[r].base_in_world * link;
    world_.setRobotLinks(r, links_[r]);
    std::copy(joints.begin(), joints.end(), placed_joints_[r].begin());
    placed_known_[r] = true;
  }
  return result;
}

ValidityResult StateValidator::checkJoints(std::span<const double> q, bool exact_distances,
                                           bool primitive_contacts_apart) {
  if (!joint_space_ || q.size() != jointCount()) {
    ValidityResult result;
    result.validity = Validity::InvalidInput;
    return result;
  }
  for (const double value : q) {
    if (!std::isfinite(value)) {
      ValidityResult result;
      result.validity = Validity::InvalidInput;
      return result;
    }
  }
  return checkDistances(placeRobotsAt(q), exact_distances, primitive_contacts_apart);
}

bool StateValidator::toolPoses(std::span<const double> q, DualPose& tools) {
  if (!joint_space_ || q.size() != jointCount()) return false;
  const SceneDescription& description = world_.scene();
  for (std::size_t r = 0; r < models_.size(); ++r) {
    const std::span<const double> joints = q.subspan(joint_offsets_[r], joint_offsets_[r + 1] - joint_offsets_[r]);
    if (!models_[r]->linkFramesAt(joints, links_[r])) return false;
    const RobotPlacement& placement = description.robots[r];
    for (std::size_t t = 0; t < placement.tool_indices.size(); ++t) {
      const KDL::Frame tool = placement.base_in_world * links_[r][models_[r]->toolLink(t)] * tool_in_model_tool_[r][t];
      (placement.tool_indices[t] == 0 ? tools.first : tools.second) = tool;
    }
  }
  return true;
}

StateValidator::Distances StateValidator::distancesAt(std::span<const double> q, std::span<double> pairs) {
  return placedDistances(joint_space_ && q.size() == jointCount() && placeRobotsAt(q).valid(), pairs);
}

StateValidator::Distances StateValidator::distancesAt(const DualPose& q, std::span<double> pairs) {
  return placedDistances(placeRobots(q).valid(), pairs);
}

StateValidator::Distances StateValidator::placedDistances(bool placed, std::span<double> pairs) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!placed) {
    std::fill(pairs.begin(), pairs.end(), kNaN);
    return {kNaN, kNaN, kNaN};
  }
  placedPairDistances(pairs);
  return placedDistances();
}

StateValidator::Distances StateValidator::placedDistances() {
  Distances distances{std::numeric_limits<double>::infinity(), world_.allowedContactDistance(),
                      world_.primitiveContactDistance()};
  // A measured state moves little between two calls: the pair closest last time is measured first
  // and bounds every group pair's search (the same minimum, most pairs never measured). Declared
  // contacts (allowed and primitive) are left out, so closest_ is never one of them.
  if (closest_.first != kNoObject) distances.clearance = world_.objectDistance(closest_.first, closest_.second);
  for (const GroupPair& pair : world_.scene().checks) {
    const GroupDistance d = world_.distanceUnder(pair.first, pair.second, distances.clearance, true);
    if (d.first_index == kNoObject || !(d.distance < distances.clearance)) continue;
    distances.clearance = d.distance;
    closest_ = {d.first_index, d.second_index};
  }
  return distances;
}

bool StateValidator::pairDistancesAt(std::span<const double> q, std::span<double> out) {
  if (!joint_space_ || q.size() != jointCount() || !placeRobotsAt(q).valid()) {
    std::fill(out.begin(), out.end(), std::numeric_limits<double>::quiet_NaN());
    return false;
  }
  placedPairDistances(out);
  return true;
}

bool StateValidator::pairDistancesAt(const DualPose& q, std::span<double> out) {
  if (!placeRobots(q).valid()) {
    std::fill(out.begin(), out.end(), std::numeric_limits<double>::quiet_NaN());
    return false;
  }
  placedPairDistances(out);
  return true;
}

void StateValidator::placedPairDistances(std::span<double> out) const {
  for (std::size_t p = 0; p < pair_objects_.size() && p < out.size(); ++p) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : pair_objects_[p]) smallest = std::min(smallest, world_.objectDistance(a, b));
    out[p] = smallest;
  }
}

ValidityResult StateValidator::check(const DualPose& q, bool exact_distances) {
  return checkDistances(placeRobots(q), exact_distances);
}

ValidityResult StateValidator::checkDistances(ValidityResult result, bool exact_distances,
                                              bool primitive_contacts_apart) {
  if (!result.valid()) return result;
  const SceneDescription& description = world_.scene();
  const double threshold = description.min_collision_distance;
  for (const GroupPair& pair : description.checks) {
    const GroupDistance d =
        world_.distance(pair.first, pair.second, exact_distances ? 0.0 : threshold, primitive_contacts_apart);
    if (d.distance <= threshold) {
      result.validity = Validity::TooClose;
      result.first_group = description.groups[pair.first];
      result.second_group = description.groups[pair.second];
      result.first_object = d.first_object;
      result.second_object = d.second_object;
      result.distance = d.distance;
      return result;
    }
  }
  return result;
}

void StateValidator::resetWarmStart() {
  for (const auto& model : models_) model->resetWarmStart();
}

double StateValidator::minimumDistance(const DualPose& q) {
  if (!placeRobots(q).valid()) return std::numeric_limits<double>::quiet_NaN();
  double minimum = std::numeric_limits<double>::infinity();
  for (const GroupPair& pair : world_.scene().checks)
    minimum = std::min(minimum, world_.distance(pair.first, pair.second).distance);
  return minimum;
}

}  // namespace cobra::planning
