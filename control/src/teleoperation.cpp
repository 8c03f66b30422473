#include "cobra/control/teleoperation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cobra::control {
namespace {

/// alpha_i of eq. 4.17-4.18: 1 up to `low`, 0 from `high`, smoothly non-increasing between.
double weight(double value, double low, double high) noexcept {
  if (value <= low) return 1.0;
  if (value >= high) return 0.0;
  return smoothFall((value - low) / (high - low));
}

void requireLevels(const TankLevels& t, const char* which) {
  if (!(t.minimum > 0.0 && t.minimum < t.request && t.request < t.available && t.available < t.maximum &&
        t.initial > t.minimum && t.initial <= t.maximum))
    throw std::invalid_argument(std::string("PassivityLayer: the ") + which +
                                " tank needs 0 < minimum < request < available < maximum and minimum < initial <= "
                                "maximum (J), got " + std::to_string(t.minimum) + ", " + std::to_string(t.request) +
                                ", " + std::to_string(t.available) + ", " + std::to_string(t.maximum) + ", initial " +
                                std::to_string(t.initial));
}

/// Eq. 4.20: the tank (energy J) pays F_idᵀ v_i dt for the force it implements and never drops below
/// `minimum` (ε); a force that takes energy from the robot (negative cost) always fills the tank.
/// Returns false, leaving `force` zero, when the tank cannot pay.
bool payForForce(const Vector3& desired, const Vector3& velocity, double dt, double minimum, double& energy,
                 Vector3& force) noexcept {
  const double cost = desired.dot(velocity) * dt;
  if (cost > 0.0 && energy - cost < minimum) return false;
  force = desired;
  energy -= cost;
  return true;
}

}  // namespace

double smoothFall(double s) noexcept {
  if (s <= 0.0) return 1.0;
  if (s >= 1.0) return 0.0;
  return 1.0 - s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
}

TransparencyLayer::TransparencyLayer(const TransparencyParameters& p) : p_(p) {
  auto positive = [](double v, const char* name, const char* unit) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("TransparencyLayer: ") + name + " must be > 0 " + unit + ", got " +
                                  std::to_string(v));
  };
  positive(p.stiffness, "stiffness", "(N/m)");
  positive(p.damping, "damping", "(N·s/m)");
  positive(p.compensation_time, "compensation_time", "(s)");
  if (!(p.error_low >= 0.0 && p.error_low < p.error_high))
    throw std::invalid_argument("TransparencyLayer: error_low < error_high (m) is needed (ē1 < ē2)");
  if (!(p.rest_low >= 0.0 && p.rest_low < p.rest_high))
    throw std::invalid_argument("TransparencyLayer: rest_low < rest_high (m) is needed (λ̄1 < λ̄2)");
}

void TransparencyLayer::engage(double time, const Vector3& master, const Vector3& slave) noexcept {
  engaged_ = true;
  full_ = false;
  start_ = time;
  offset_ = master - slave;
  rest_ = offset_;
  alpha_ = 0.0;
}

void TransparencyLayer::compute(double time, const Vector3& master, const Vector3& master_velocity,
                                const Vector3& slave, const Vector3& slave_velocity, Vector3& master_force,
                                Vector3& slave_force) noexcept {
  if (!engaged_) {
    master_force.setZero();
    slave_force.setZero();
    return;
  }
  rest_ = offset_ * smoothFall((time - start_) / p_.compensation_time);  // l(t): L at t_s, 0 from t_s + t_c
  if (!full_) {
    alpha_ = weight((master - slave).norm(), p_.error_low, p_.error_high) *
             weight(rest_.norm(), p_.rest_low, p_.rest_high);
    if (alpha_ >= 1.0) full_ = true;  // t_M: from now on alpha = 1 (eq. 4.16)
  }
  if (full_) alpha_ = 1.0;
  const Vector3 coupling = p_.stiffness * (master - slave - rest_) + p_.damping * (master_velocity - slave_velocity);
  master_force = -coupling;
  slave_force = alpha_ * coupling;
}

PassivityLayer::PassivityLayer(const PassivityParameters& p) : p_(p) {
  requireLevels(p.master, "master");
  requireLevels(p.slave, "slave");
  if (!(p.transfer_power > 0.0)) throw std::invalid_argument("PassivityLayer: transfer_power must be > 0 W");
  master_ = p.master.initial;
  slave_ = p.slave.initial;
}

PassivityStep PassivityLayer::step(double dt, const Vector3& master_desired, const Vector3& slave_desired,
                                   const Vector3& master_velocity, const Vector3& slave_velocity,
                                   double master_dissipation, double slave_dissipation) noexcept {
  PassivityStep out;
  if (!(dt > 0.0)) return out;
  const TankLevels& lm = p_.master;
  const TankLevels& ls = p_.slave;
  const double sigma_m = master_ <= lm.maximum ? 1.0 : 0.0;  // eq. 4.7 per tank
  const double sigma_s = slave_ <= ls.maximum ? 1.0 : 0.0;
  const double dm = std::max(master_dissipation, 0.0) * dt, ds = std::max(slave_dissipation, 0.0) * dt;
  // Eq. 4.21-4.23: a full tank passes its dissipation on; a rich tank feeds one that asks, at P̄.
  const double request_m = master_ < lm.request ? 1.0 : 0.0, request_s = slave_ < ls.request ? 1.0 : 0.0;
  const double give_m = master_ >= lm.available ? 1.0 : 0.0, give_s = slave_ >= ls.available ? 1.0 : 0.0;
  const double out_m = (1.0 - sigma_m) * dm + request_s * give_m * p_.transfer_power * dt;
  const double out_s = (1.0 - sigma_s) * ds + request_m * give_s * p_.transfer_power * dt;
  double master_next = master_ + sigma_m * dm + sigma_m * out_s - out_m;
  double slave_next = slave_ + sigma_s * ds + sigma_s * out_m - out_s;
  spilled_ += (1.0 - sigma_m) * out_s + (1.0 - sigma_s) * out_m;
  out.master_limited = !payForForce(master_desired, master_velocity, dt, lm.minimum, master_next, out.master_force);
  out.slave_limited = !payForForce(slave_desired, slave_velocity, dt, ls.minimum, slave_next, out.slave_force);
  master_ = master_next;
  slave_ = slave_next;
  return out;
}

}  // namespace cobra::control
