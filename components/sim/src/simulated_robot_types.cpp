// The robots SimulatedServoRobotBase drives: their kinematics adapters and defaults, and the Endo
// Stitch actuation of the two-armed I-SUR.
#include <cmath>
#include <optional>
#include <stdexcept>

#include "cobra/components/sim/simulated_robot.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/isur_continuity.hpp"
#include "cobra/kinematics/ur5.hpp"

namespace cobra::components {
namespace {

/// One tool: a KinematicsSolver behind kinematics::ContinuousIk.
class SingleToolKinematics final : public SimulatedRobotKinematics {
 public:
  explicit SingleToolKinematics(std::unique_ptr<kinematics::KinematicsSolver> solver) : solver_(std::move(solver)) {}
  std::size_t toolCount() const noexcept override { return 1; }
  const kinematics::JointLimits& limits() const noexcept override { return solver_->limits(); }
  kinematics::IkStatus forward(const KDL::JntArray& q, std::span<KDL::Frame> tools) noexcept override {
    return solver_->forward(q, tools[0]);
  }
  void setContinuity(const std::vector<double>& max_velocity, double period) override {
    continuity_.emplace(*solver_, max_velocity, period);
  }
  kinematics::IkStatus solve(std::span<const KDL::Frame> targets, const KDL::JntArray& current, double dt,
                             KDL::JntArray& q_out) noexcept override {
    return continuity_->solve(targets[0], current, dt, q_out);
  }

 private:
  std::unique_ptr<kinematics::KinematicsSolver> solver_;
  std::optional<kinematics::ContinuousIk> continuity_;
};

/// The two-armed I-SUR: tool 0 the Endo Stitch tip, tool 1 the gripper; the split IK of §5.4.1
/// behind kinematics::ContinuousIsurSuturingIk.
class SuturingKinematics final : public SimulatedRobotKinematics {
 public:
  std::size_t toolCount() const noexcept override { return 2; }
  const kinematics::JointLimits& limits() const noexcept override { return solver_.limits(); }
  kinematics::IkStatus forward(const KDL::JntArray& q, std::span<KDL::Frame> tools) noexcept override {
    return solver_.forward(q, tools[0], tools[1]);
  }
  void setContinuity(const std::vector<double>& max_velocity, double period) override {
    continuity_.emplace(solver_, max_velocity, period);
  }
  kinematics::IkStatus solve(std::span<const KDL::Frame> targets, const KDL::JntArray& current, double dt,
                             KDL::JntArray& q_out) noexcept override {
    return continuity_->solve(targets[0], targets[1], current, dt, q_out);
  }

 private:
  kinematics::IsurSuturingSolver solver_;
  std::optional<kinematics::ContinuousIsurSuturingIk> continuity_;
};

constexpr double kSliderVelocity = 0.1;      // m/s
constexpr double kRevoluteVelocity = 1.5;    // rad/s
constexpr double kSliderCounts = 1e6;        // counts/m (1 µm)
constexpr double kRevoluteCounts = 262144;   // counts/rev (2^18)

}  // namespace

SimulatedISURRobot::SimulatedISURRobot(std::string name)
    : SimulatedServoRobotBase(
          std::move(name),
          "Simulated I-SUR puncturing robot (thesis §4.5.7 interface): stiff servo, IK, ATI Nano17 at the needle",
          SimulatedRobotDefaults{
              .robot = "I-SUR",
              .initial_joints = {0.1, 0.1, 0.1, 0.0, 0.0, 0.6, 0.6, 0.0},
              .max_velocity = {kSliderVelocity, kSliderVelocity, kSliderVelocity, kRevoluteVelocity,
                               kRevoluteVelocity, kRevoluteVelocity, kRevoluteVelocity, kRevoluteVelocity},
              .encoder_counts = {kSliderCounts, kSliderCounts, kSliderCounts, kRevoluteCounts, kRevoluteCounts,
                                 kRevoluteCounts, kRevoluteCounts, kRevoluteCounts},
              .tools = {SimulatedToolDefaults{
                  .port_infix = "", .property_prefix = "", .sensor = "atiNano17", .what = ""}},
              .twist_ports = false}) {}

std::unique_ptr<SimulatedRobotKinematics> SimulatedISURRobot::makeKinematics() const {
  return std::make_unique<SingleToolKinematics>(std::make_unique<kinematics::IsurPuncturingSolver>());
}

SimulatedUR5Robot::SimulatedUR5Robot(std::string name)
    : SimulatedServoRobotBase(
          std::move(name),
          "Simulated UR5 (thesis §4.5.8 interface): stiff servo, closed-form IK, twist commands, ATI Nano43",
          SimulatedRobotDefaults{.robot = "UR5",
                                 .initial_joints = {0.0, -1.57, 1.57, -1.57, -1.57, 0.0},
                                 .max_velocity = std::vector<double>(6, 3.14),
                                 .encoder_counts = std::vector<double>(6, kRevoluteCounts),
                                 .tools = {SimulatedToolDefaults{
                                     .port_infix = "", .property_prefix = "", .sensor = "atiNano43", .what = ""}},
                                 .twist_ports = true}) {}

std::unique_ptr<SimulatedRobotKinematics> SimulatedUR5Robot::makeKinematics() const {
  return std::make_unique<SingleToolKinematics>(std::make_unique<kinematics::Ur5Solver>());
}

namespace {

SimulatedRobotDefaults suturingDefaults() {
  SimulatedRobotDefaults d{
      .robot = "I-SUR suturing",
      .initial_joints = {0.1, 0.1, 0.1, 0.0, 0.0, 0.75, 0.45, 0.0, 0.0, 0.5, -0.5, 0.0, 0.5, 0.0},
      .max_velocity = std::vector<double>(14, kRevoluteVelocity),
      .encoder_counts = std::vector<double>(14, kRevoluteCounts),
      .tools = {SimulatedToolDefaults{.port_infix = "Right",
                                      .property_prefix = "right_",
                                      .sensor = "atiNano43",
                                      .what = "Right: the Endo Stitch tip"},
                SimulatedToolDefaults{.port_infix = "Left",
                                      .property_prefix = "left_",
                                      .sensor = "atiNano17",
                                      .what = "Left: the stick's tip held by the gripper"}},
      .twist_ports = false};
  for (std::size_t j = 0; j < 3; ++j) {
    d.max_velocity[j] = kSliderVelocity;
    d.encoder_counts[j] = kSliderCounts;
  }
  return d;
}

}  // namespace

SimulatedISURSuturingRobot::SimulatedISURSuturingRobot(std::string name)
    : SimulatedServoRobotBase(std::move(name),
                              "Simulated two-armed I-SUR suturing robot (thesis §5.3): stiff servo, split IK (§5.4.1), "
                              "ATI Nano43 at the Endo Stitch, Nano17 at the stick, Endo Stitch actuation",
                              suturingDefaults()) {
  addProperty(actuate_event_);
  addProperty(actuation_time_);
  addEventPort(input_events_);
  addPort(actuations_);
}

std::unique_ptr<SimulatedRobotKinematics> SimulatedISURSuturingRobot::makeKinematics() const {
  return std::make_unique<SuturingKinematics>();
}

bool SimulatedISURSuturingRobot::configureHook() {
  if (!(std::isfinite(actuation_time_()) && actuation_time_() > 0.0))
    return refuse("property actuation_time is " + std::to_string(actuation_time_()) + " s; expected > 0 s");
  const std::string& event = actuate_event_();
  if (event.empty() || event.size() > core::BoundedString<63>::capacity())
    return refuse("property actuate_event is '" + event + "'; expected an event name of 1 to 63 characters");
  if (!SimulatedServoRobotBase::configureHook()) return false;
  actuate_name_.assign(event);
  actuation_done_ns_ = -1;
  completed_ = 0;
  actuations_.write(0);
  return true;
}

bool SimulatedISURSuturingRobot::startHook() {
  core::Event stale;
  while (input_events_.readNew(stale) == core::FlowStatus::NewData) {
  }  // requests sent before the start are not this run's
  actuation_done_ns_ = -1;
  return SimulatedServoRobotBase::startHook();
}

void SimulatedISURSuturingRobot::updateHook() {
  SimulatedServoRobotBase::updateHook();
  const std::int64_t now_ns = now().count();
  // A completed actuation first: a request in the step it completes starts the next one.
  if (actuation_done_ns_ >= 0 && now_ns >= actuation_done_ns_) {
    actuation_done_ns_ = -1;
    ++completed_;
    emitEvent("e_endo_stitch_actuated");
  }
  core::Event request;
  while (input_events_.readNew(request) == core::FlowStatus::NewData) {
    if (request.name != actuate_name_) continue;
    if (actuation_done_ns_ >= 0) {
      emitEvent("e_endo_stitch_busy");
      continue;
    }
    actuation_done_ns_ = now_ns + static_cast<std::int64_t>(std::llround(actuation_time_() * 1e9));
  }
  actuations_.write(completed_);
}

}  // namespace cobra::components
