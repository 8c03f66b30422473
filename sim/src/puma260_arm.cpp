#include "cobra/sim/puma260_arm.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::sim {
namespace {

void requireAtLeast(const char* parameter, double value, double minimum, bool inclusive, const char* unit) {
  if (!std::isfinite(value) || value < minimum || (!inclusive && value == minimum)) {
    throw std::invalid_argument(std::string("Puma 260 arm: ") + parameter + " = " + std::to_string(value) +
                                ", expected " + (inclusive ? ">= " : "> ") + std::to_string(minimum) + " " + unit);
  }
}

std::array<Cia402Drive, 6> makeDrives(const Puma260ArmModel& model, const std::array<double, 6>& q) {
  validate(model);
  return {Cia402Drive(model.drives[0], q[0]), Cia402Drive(model.drives[1], q[1]), Cia402Drive(model.drives[2], q[2]),
          Cia402Drive(model.drives[3], q[3]), Cia402Drive(model.drives[4], q[4]), Cia402Drive(model.drives[5], q[5])};
}

}  // namespace

Puma260ArmModel Puma260ArmModel::defaults() {
  Puma260ArmModel model;
  const double inertia[6] = {0.05, 0.08, 0.03, 0.005, 0.005, 0.005};
  for (std::size_t i = 0; i < 6; ++i) model.drives[i].inertia = inertia[i];
  return model;
}

void validate(const Puma260ArmModel& m) {
  for (std::size_t i = 0; i < m.drives.size(); ++i) {
    try {
      validate(m.drives[i]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("Puma 260 arm: joint " + std::to_string(i + 1) + ": " + e.what());
    }
  }
  requireAtLeast("upper_arm_mass", m.upper_arm_mass, 0.0, true, "kg");
  requireAtLeast("upper_arm_com", m.upper_arm_com, 0.0, true, "m");
  requireAtLeast("forearm_mass", m.forearm_mass, 0.0, true, "kg");
  requireAtLeast("forearm_com", m.forearm_com, 0.0, true, "m");
  requireAtLeast("upper_arm_length", m.upper_arm_length, 0.0, false, "m");
  requireAtLeast("gravity", m.gravity, 0.0, true, "m/s^2");
  requireAtLeast("brake_torque", m.brake_torque, 0.0, true, "N*m");
}

Puma260Arm::Puma260Arm(const Puma260ArmModel& model, const std::array<double, 6>& initial)
    : model_(model), drives_(makeDrives(model, initial)) {}

std::array<double, 6> Puma260Arm::gravityTorque(const std::array<double, 6>& q) const noexcept {
  const Puma260ArmModel& m = model_;
  const double forearm = m.gravity * m.forearm_mass * m.forearm_com * std::sin(q[1] + q[2]);
  std::array<double, 6> tau{};
  tau[1] =
      m.gravity * (m.upper_arm_mass * m.upper_arm_com + m.forearm_mass * m.upper_arm_length) * std::cos(q[1]) - forearm;
  tau[2] = -forearm;
  return tau;
}

void Puma260Arm::step(double dt) noexcept {
  if (!std::isfinite(dt) || dt <= 0.0) return;
  std::array<double, 6> q{};
  for (std::size_t i = 0; i < 6; ++i) q[i] = drives_[i].position();
  const std::array<double, 6> tau = gravityTorque(q);
  for (std::size_t i = 0; i < 6; ++i) {
    // Unpowered joints are held by their brakes against gravity.
    const Cia402State s = drives_[i].state();
    const bool powered = s == Cia402State::OperationEnabled || s == Cia402State::QuickStopActive;
    // The brake opposes the motion with at most brake_torque, just enough to stop the joint within
    // this step; at rest it holds whatever gravity asks.
    const double v = drives_[i].velocity();
    const double brake = std::copysign(std::min(model_.brake_torque, model_.drives[i].inertia * std::abs(v) / dt), v);
    drives_[i].setLoadTorque(powered ? tau[i] : brake);
    drives_[i].step(dt);
  }
}

}  // namespace cobra::sim
