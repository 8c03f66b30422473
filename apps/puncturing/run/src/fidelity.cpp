#include "cobra/puncturing/fidelity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "cobra/planning/robot_adapters.hpp"
#include "cobra/planning/state_validator.hpp"

namespace cobra::puncturing {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
constexpr int kLoggedEpisodes = 10;  // joint jump episodes described in joint_jump_log

void raise(Worst& worst, double value, double t, const std::string& state) {
  if (!(value > worst.value)) return;
  worst = {value, t, state};
}

double maxOrNan(double window, double value) { return std::isnan(window) ? value : std::max(window, value); }

}  // namespace

TrackingMonitor::TrackingMonitor(std::string robot, std::vector<double> max_velocity, double period)
    : max_velocity_(std::move(max_velocity)), period_(period) {
  figures_.robot = std::move(robot);
}

void TrackingMonitor::step(double t, bool counts, const std::string& state, const KDL::Frame& commanded,
                           const KDL::Frame& measured, const KDL::JntArray* joints) {
  const double mm = 1000.0 * (commanded.p - measured.p).Norm();
  KDL::Vector axis;
  const double deg = kRadToDeg * (commanded.M.Inverse() * measured.M).GetRotAngle(axis);
  last_mm_ = mm;
  last_deg_ = deg;
  window_mm_ = maxOrNan(window_mm_, mm);
  window_deg_ = maxOrNan(window_deg_, deg);
  if (counts) {
    figures_.seconds_sampled += period_;
    raise(figures_.position_mm, mm, t, state);
    raise(figures_.orientation_deg, deg, t, state);
    if (mm > 5.0) figures_.seconds_above_5mm += period_;
  }
  if (joints == nullptr || max_velocity_.empty() || joints->rows() != max_velocity_.size()) {
    have_joints_ = false;
    return;
  }
  if (have_joints_ && counts) {
    double fraction = 0.0;
    unsigned fastest = 0;
    for (unsigned i = 0; i < joints->rows(); ++i) {
      const double f = std::abs((*joints)(i) - previous_joints_(i)) / (max_velocity_[i] * period_);
      if (f > fraction) fraction = f, fastest = i;
    }
    raise(figures_.joint_speed, fraction, t, state);
    if (!in_episode_ && fraction >= kSaturated) {
      in_episode_ = true;
      if (figures_.joint_jumps++ < kLoggedEpisodes) {
        char line[200];
        std::snprintf(line, sizeof line, "%.3f s joint %u at %.0f %% of its velocity limit (%s)\n", t, fastest + 1,
                      100.0 * fraction, state.c_str());
        figures_.joint_jump_log += line;
      }
    } else if (in_episode_ && fraction < kCalm) {
      in_episode_ = false;
    }
  } else if (!counts) {
    in_episode_ = false;
  }
  previous_joints_ = *joints;
  have_joints_ = true;
}

std::pair<double, double> TrackingMonitor::takeWindowMaximum() {
  const std::pair<double, double> out{window_mm_, window_deg_};
  window_mm_ = window_deg_ = std::numeric_limits<double>::quiet_NaN();
  return out;
}

ClearanceMonitor::ClearanceMonitor(planning::SceneDescription scene, std::vector<AllowedContact> contacts)
    : contacts_(std::move(contacts)), threshold_(scene.min_collision_distance) {
  for (const auto& [a, b] : scene.allowed_contacts) {
    const bool declared = std::any_of(contacts_.begin(), contacts_.end(), [&](const AllowedContact& c) {
      return (c.first_object == a && c.second_object == b) || (c.first_object == b && c.second_object == a);
    });
    if (!declared)
      throw std::invalid_argument("clearance: the scene allows contact " + a + "/" + b +
                                  " but it is not among the declared allowed contacts");
  }
  // Every contact object goes to a group of its own ("contact:NAME"); each checked pair of groups
  // becomes the checks between their parts, except the contact pairs, measured apart.
  const std::size_t original_groups = scene.groups.size();
  std::map<std::string, std::size_t> own_group;  // object -> its new group
  std::vector<std::vector<std::size_t>> parts(original_groups);
  for (std::size_t g = 0; g < original_groups; ++g) parts[g].push_back(g);
  for (const AllowedContact& c : contacts_) {
    for (const std::string& name : {c.first_object, c.second_object}) {
      const std::size_t index = scene.objectIndex(name);
      if (index == planning::SceneDescription::npos)
        throw std::invalid_argument("clearance: allowed contact '" + c.name + "': the planning scene has no object '" +
                                    name + "'");
      if (own_group.count(name)) continue;
      const std::size_t from = scene.groupIndex(scene.objects[index].group);
      own_group[name] = scene.groups.size();
      parts[from].push_back(scene.groups.size());
      scene.groups.push_back("contact:" + name);
      scene.objects[index].group = scene.groups.back();
    }
  }
  for (const AllowedContact& c : contacts_)
    contact_groups_.push_back({own_group[c.first_object], own_group[c.second_object]});
  auto isContact = [&](std::size_t a, std::size_t b) {
    for (ContactGroups& c : contact_groups_) {
      if ((a == c.first && b == c.second) || (a == c.second && b == c.first)) return c.checked = true;
    }
    return false;
  };
  std::vector<planning::GroupPair> checks;
  for (const planning::GroupPair& pair : scene.checks)
    for (const std::size_t a : parts[pair.first])
      for (const std::size_t b : parts[pair.second])
        if (!isContact(a, b)) checks.push_back({a, b});
  scene.checks = std::move(checks);
  scene.allowed_contacts.clear();
  scene.validate();
  planning::RobotModels models = planning::makeRobotModels(scene);
  validator_ = std::make_unique<planning::StateValidator>(std::move(scene), models);
  for (const planning::RobotPlacement& robot : validator_->scene().robots) models_.push_back(models.at(robot.name));
}

ClearanceMonitor::~ClearanceMonitor() = default;

bool ClearanceMonitor::refused(std::size_t contact, const std::vector<bool>& allowed) const {
  return contact_groups_[contact].checked && contact < allowed.size() && !allowed[contact];
}

std::size_t ClearanceMonitor::robotIndex(const std::string& name) const { return validator_->scene().robotIndex(name); }

ClearanceSample ClearanceMonitor::measure(const KDL::Frame& needle, const KDL::Frame& probe,
                                          const std::vector<bool>& allowed, const std::vector<KDL::JntArray>& joints,
                                          bool name_closest) {
  for (std::size_t r = 0; r < joints.size() && r < models_.size(); ++r) {
    if (joints[r].rows() == 0) continue;
    try {
      if (auto* isur = dynamic_cast<planning::IsurPuncturingModel*>(models_[r].get())) {
        isur->setSeed(joints[r]);
        isur->resetWarmStart();
      } else if (auto* ur5 = dynamic_cast<planning::Ur5Model*>(models_[r].get())) {
        ur5->setSeed(joints[r]);
        ur5->resetWarmStart();
      }
    } catch (const std::invalid_argument&) {
      // Joints of another size than the model's: keep the IK's own warm start.
    }
  }
  ClearanceSample sample;
  sample.clearance = validator_->minimumDistance({needle, probe});
  if (std::isnan(sample.clearance)) return sample;
  const planning::CollisionWorld& world = validator_->world();
  for (std::size_t i = 0; i < contact_groups_.size(); ++i) {
    const double d = world.distance(contact_groups_[i].first, contact_groups_[i].second).distance;
    sample.contacts.push_back(d);
    if (refused(i, allowed)) sample.clearance = std::min(sample.clearance, d);
  }
  if (!name_closest) return sample;
  double closest = std::numeric_limits<double>::infinity();
  auto consider = [&](double d, std::string pair) {
    if (d <= threshold_) sample.under_threshold.emplace_back(pair, d);
    if (d < closest) closest = d, sample.closest = std::move(pair);
  };
  for (const planning::GroupPair& pair : validator_->scene().checks) {
    const planning::GroupDistance d = world.distance(pair.first, pair.second);
    consider(d.distance, std::string(d.first_object) + "/" + std::string(d.second_object));
  }
  for (std::size_t i = 0; i < contact_groups_.size(); ++i)
    if (refused(i, allowed)) consider(sample.contacts[i], contacts_[i].first_object + "/" + contacts_[i].second_object);
  return sample;
}

}  // namespace cobra::puncturing
