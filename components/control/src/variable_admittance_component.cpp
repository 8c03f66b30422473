#include "cobra/components/control/variable_admittance_component.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

bool matrixFromProperty(const std::vector<double>& values, control::Matrix6& out) noexcept {
  if (values.size() == 6) {
    out.setZero();
    for (int i = 0; i < 6; ++i) out(i, i) = values[static_cast<std::size_t>(i)];
    return true;
  }
  if (values.size() == 36) {
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) out(r, c) = values[static_cast<std::size_t>(6 * r + c)];
    return true;
  }
  return false;
}

namespace {

bool finiteWrench(const KDL::Wrench& w) noexcept {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(w(i))) return false;
  return true;
}

bool finitePose(const KDL::Frame& f) noexcept {
  for (double v : f.M.data)
    if (!std::isfinite(v)) return false;
  return std::isfinite(f.p.x()) && std::isfinite(f.p.y()) && std::isfinite(f.p.z());
}

}  // namespace

VariableAdmittanceController::VariableAdmittanceController(std::string name)
    : Component(std::move(name), core::Role::Calculation,
                "Variable admittance with energy tank (thesis §4.5.3): passive whatever its parameters' schedule") {
  for (core::PropertyBase* p : std::initializer_list<core::PropertyBase*>{
           &inertia_, &damping_, &stiffness_, &constant_inertia_, &constant_stiffness_, &tank_initial_, &tank_max_,
           &tank_min_, &max_reference_speed_, &max_reference_angular_speed_, &wrench_timeout_})
    addProperty(*p);
  addPort(ref_pose_);
  addPort(ref_twist_);
  addPort(meas_wrench_);
  addPort(ext_wrench_);
  addPort(held_pose_);
  addPort(held_ref_pose_);
  addPort(adm_pose_);
  addPort(adm_twist_);
  addPort(tank_energy_);
  addPort(dissipated_power_);
  addOperation("lastFailure", std::function<std::string()>([this] { return lastFailure(); }),
               "the last non-finite input refused: when and on which port (the admittance then holds)",
               core::ExecutionThread::Client);
}

std::string VariableAdmittanceController::lastFailure() const {
  const char* port = refused_port_.load(std::memory_order_acquire);
  if (port == nullptr) return "no non-finite input refused";
  char at[48];
  std::snprintf(at, sizeof at, "at %.3f s ", std::chrono::duration<double>(std::chrono::nanoseconds(
                                                 refused_at_.load(std::memory_order_relaxed))).count());
  return at + name() + " refused a non-finite " + port + " sample; it holds its last admPose";
}

VariableAdmittanceController::~VariableAdmittanceController() = default;

bool VariableAdmittanceController::configureHook() {
  control::AdmittanceParameters p;
  const std::pair<core::Property<std::vector<double>>*, control::Matrix6*> matrices[] = {
      {&inertia_, &p.inertia}, {&damping_, &p.damping}, {&stiffness_, &p.stiffness},
      {&constant_inertia_, &p.constant_inertia}, {&constant_stiffness_, &p.constant_stiffness}};
  for (const auto& [property, matrix] : matrices)
    if (!matrixFromProperty((*property)(), *matrix))
      return refuse("property " + property->name() + " has " + std::to_string((*property)().size()) +
                    " numbers; give 6 (the diagonal) or 36 (row-major)");
  if (!(max_reference_speed_() > 0.0) || !(max_reference_angular_speed_() > 0.0))
    return refuse("properties max_reference_speed (" + std::to_string(max_reference_speed_()) +
                  " m/s) and max_reference_angular_speed (" + std::to_string(max_reference_angular_speed_()) +
                  " rad/s) must be > 0");
  if (!(wrench_timeout_() >= 0.0) || !std::isfinite(wrench_timeout_()))
    return refuse("property wrench_timeout is " + std::to_string(wrench_timeout_()) + " s; expected >= 0 s (0: never hold)");
  p.tank = {tank_initial_(), tank_max_(), tank_min_()};
  try {
    controller_ = std::make_unique<control::VariableAdmittance>(p);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  applied_inertia_ = inertia_();
  applied_damping_ = damping_();
  applied_stiffness_ = stiffness_();
  applied_inertia_.reserve(36);
  applied_damping_.reserve(36);
  applied_stiffness_.reserve(36);
  return true;
}

bool VariableAdmittanceController::startHook() {
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: its period is the control period");
  controller_->reset();
  have_reference_ = false;
  stepped_ = false;
  tank_empty_ = false;
  following_held_ = resynced_ = false;
  blind_ = false;
  not_finite_ = false;
  last_wrench_ = now();
  return true;
}

bool VariableAdmittanceController::referenceJumped(double dt) const noexcept {
  // Compared squared and through the cosine (no square root, no axis): the step moved by
  // |Δp| > v_max·dt, or turned by θ > ω_max·dt where 1 + 2 cos θ = trace(R_prevᵀ R), the sum of
  // the two matrices' elementwise products.
  const KDL::Vector moved = reference_.p - previous_reference_.p;
  const double step = max_reference_speed_() * dt;
  if (KDL::dot(moved, moved) > step * step) return true;
  const double turn = max_reference_angular_speed_() * dt;
  if (!(turn < std::numbers::pi)) return false;  // no rotation exceeds π
  double trace = 0.0;
  for (int i = 0; i < 9; ++i) trace += previous_reference_.M.data[i] * reference_.M.data[i];
  return 0.5 * (trace - 1.0) < std::cos(turn);
}

void VariableAdmittanceController::updateHook() {
  // A configuration changed the matrices: hand them over (the state, hence the pose, is kept).
  if (inertia_() != applied_inertia_ || damping_() != applied_damping_ || stiffness_() != applied_stiffness_) {
    control::Matrix6 inertia, damping, stiffness;
    const bool sizes = matrixFromProperty(inertia_(), inertia) && matrixFromProperty(damping_(), damping) &&
                       matrixFromProperty(stiffness_(), stiffness);
    if (sizes && controller_->setParameters(inertia, damping, stiffness) == control::AdmittanceStatus::Ok) {
      applied_inertia_ = inertia_();
      applied_damping_ = damping_();
      applied_stiffness_ = stiffness_();
    } else {
      emitEvent("e_bad_parameters");
      applied_inertia_ = inertia_();  // report once per change
      applied_damping_ = damping_();
      applied_stiffness_ = stiffness_();
    }
  }
  // After a re-sync only a new reference sample replaces the held one (the old sample is the
  // set-point the robot refused, or one it was never sent).
  KDL::Frame reference;
  KDL::Twist reference_twist;
  const core::FlowStatus reference_status = ref_pose_.read(reference);
  const core::FlowStatus twist_status = ref_twist_.read(reference_twist);
  if (reference_status == core::FlowStatus::NewData ||
      (reference_status == core::FlowStatus::OldData && !following_held_)) {
    reference_ = reference;
    have_reference_ = true;
    following_held_ = false;
  }
  if (twist_status != core::FlowStatus::NoData && !following_held_) reference_twist_ = reference_twist;
  bool resumed = false;
  if (meas_wrench_.read(wrench_) == core::FlowStatus::NewData) {
    last_wrench_ = now();
    if (blind_) {
      blind_ = false;
      resumed = true;
      emitEvent("e_wrench_restored");
    }
  }
  if (ext_wrench_.read(ext_wrench_value_) == core::FlowStatus::NoData) ext_wrench_value_ = KDL::Wrench::Zero();
  // A non-finite wrench is refused before anything uses it (the step, a re-sync): the output holds.
  const char* refused = !finiteWrench(wrench_) ? "measWrench" : !finiteWrench(ext_wrench_value_) ? "extWrench" : nullptr;
  if (refused != nullptr) {
    if (!not_finite_) {
      not_finite_ = true;
      refused_at_.store(now().count(), std::memory_order_relaxed);
      refused_port_.store(refused, std::memory_order_release);
      emitEvent("e_input_not_finite");
    }
    adm_twist_.write(KDL::Twist::Zero());
    dissipated_power_.write(0.0);
    holdProducer();
    return;  // admPose keeps its last sample: the robot holds where it is
  }
  not_finite_ = false;
  if (!have_reference_) return;
  KDL::Frame held;
  const bool resynced_before = resynced_;
  resynced_ = false;
  if (held_pose_.read(held) == core::FlowStatus::NewData && stepped_ && finitePose(held)) {
    // The robot holds at `held`: the output restarts there, at rest, in this very step.
    controller_->resync(held, wrench_ + ext_wrench_value_, reference_);
    reference_twist_ = KDL::Twist::Zero();
    previous_reference_ = reference_;
    following_held_ = true;
    held_ref_pose_.write(reference_);
    adm_pose_.write(held);
    adm_twist_.write(KDL::Twist::Zero());
    tank_energy_.write(controller_->tankEnergy());
    dissipated_power_.write(0.0);
    if (!resynced_before) emitEvent("e_resynced");  // once while held step after step
    resynced_ = true;
    return;
  }
  if (resumed && stepped_) {
    // The reference moved on while the admittance held (e.g. a stop motion): rebase as for a
    // reference jump, so admPose resumes from where it was held.
    controller_->rebase(previous_reference_, reference_);
    previous_reference_ = reference_;
  }
  const double dt = std::chrono::duration<double>(activity().period()).count();
  if (wrench_timeout_() > 0.0 && std::chrono::duration<double>(now() - last_wrench_).count() > wrench_timeout_()) {
    if (!blind_) {
      blind_ = true;
      emitEvent("e_wrench_lost");
    }
    adm_twist_.write(KDL::Twist::Zero());
    dissipated_power_.write(0.0);
    return;  // admPose keeps its last sample: the robot holds where it is
  }
  if (stepped_ && referenceJumped(dt)) {
    controller_->rebase(previous_reference_, reference_);
    emitEvent("e_reference_jump");
  }
  previous_reference_ = reference_;
  stepped_ = true;
  KDL::Frame pose;
  KDL::Twist twist;
  const control::AdmittanceStatus status =
      controller_->step(reference_, reference_twist_, wrench_ + ext_wrench_value_, dt, pose, twist);
  if (status == control::AdmittanceStatus::BadInput) return;
  const bool empty = status == control::AdmittanceStatus::TankEmpty;
  if (empty != tank_empty_) emitEvent(empty ? "e_tank_empty" : "e_tank_refilled");
  tank_empty_ = empty;
  adm_pose_.write(pose);
  adm_twist_.write(twist);
  tank_energy_.write(controller_->tankEnergy());
  dissipated_power_.write(controller_->dissipatedPower());
}

void VariableAdmittanceController::holdProducer() noexcept {
  // The reference the last output was stepped about (reference_ may have moved on since): the
  // producer's set-point goes back to it, so a resumed step continues from admPose without a jump.
  if (stepped_) held_ref_pose_.write(previous_reference_);
}

void VariableAdmittanceController::exceptionHook() {
  // Nothing steps any more: admPose keeps its last sample (the robot holds there), and the
  // producer of refPose is told, so that the other arms of its motion stop with this one.
  adm_twist_.write(KDL::Twist::Zero());
  holdProducer();
}

}  // namespace cobra::components
