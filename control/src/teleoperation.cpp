#include "cobra/control/teleoperation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

/// `value` in the shortest decimal form ("-1", "0.5", "2e+04") for messages.
std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// The tank's levels, named as the PassivityLayer component's properties (`which`_minimum, ...).
void requireLevels(const TankLevels& t, const std::string& which) {
  auto fail = [&](const char* level, double value, const std::string& rule) {
    throw std::invalid_argument("PassivityLayer: " + which + "_" + level + " = " + number(value) + " J: must be " +
                                rule + " (0 < minimum < request < available < maximum, minimum < initial <= maximum)");
  };
  if (!(t.minimum > 0.0) || !std::isfinite(t.minimum)) fail("minimum", t.minimum, "> 0");
  if (!(t.request > t.minimum)) fail("request", t.request, "> " + which + "_minimum = " + number(t.minimum) + " J");
  if (!(t.available > t.request))
    fail("available", t.available, "> " + which + "_request = " + number(t.request) + " J");
  if (!(t.maximum > t.available) || !std::isfinite(t.maximum))
    fail("maximum", t.maximum, "> " + which + "_available = " + number(t.available) + " J");
  if (!(t.initial > t.minimum && t.initial <= t.maximum))
    fail("initial", t.initial,
         "in (" + which + "_minimum, " + which + "_maximum] = (" + number(t.minimum) + ", " + number(t.maximum) + "] J");
}

/// Eq. 4.20: the tank (energy J) pays F_idᵀ t_i dt for the wrench it implements (the full power
/// port: force·v + torque·ω) and never drops below `minimum` (ε); a wrench that takes energy from
/// the robot (negative cost) always fills the tank. Returns false, leaving `wrench` zero, when
/// the tank cannot pay, or when the wrench or the twist is not finite (a NaN would otherwise pass
/// and turn the tank into NaN, after which no comparison limits anything again).
bool payForWrench(const Vector6& desired, const Vector6& twist, double dt, double minimum, double& energy,
                  Vector6& wrench) noexcept {
  const double cost = desired.dot(twist) * dt;
  if (!std::isfinite(cost) || !desired.allFinite()) return false;
  if (cost > 0.0 && energy - cost < minimum) return false;
  wrench = desired;
  energy -= cost;
  return true;
}

Vector3 vector(const KDL::Vector& v) noexcept { return {v.x(), v.y(), v.z()}; }

/// Exp of a rotation vector (rad) as a KDL rotation.
KDL::Rotation exp(const Vector3& r) noexcept {
  const double angle = r.norm();
  return angle < 1e-15 ? KDL::Rotation::Identity() : KDL::Rotation::Rot2(KDL::Vector(r.x(), r.y(), r.z()) / angle, angle);
}

}  // namespace

double smoothFall(double s) noexcept {
  if (s <= 0.0) return 1.0;
  if (s >= 1.0) return 0.0;
  return 1.0 - s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
}

TransparencyLayer::TransparencyLayer(const TransparencyParameters& p) : p_(p) {
  auto fail = [](const char* name, double value, const char* unit, const std::string& rule) {
    throw std::invalid_argument(std::string("TransparencyLayer: ") + name + " = " + number(value) + " " + unit +
                                ": must be " + rule);
  };
  auto positive = [&](double v, const char* name, const char* unit) {
    if (!(v > 0.0) || !std::isfinite(v)) fail(name, v, unit, "> 0");
  };
  auto nonNegative = [&](double v, const char* name, const char* unit) {
    if (!(v >= 0.0) || !std::isfinite(v)) fail(name, v, unit, ">= 0");
  };
  auto band = [&](double low, double high, const char* low_name, const char* high_name, const char* unit) {
    nonNegative(low, low_name, unit);
    if (!(high > low) || !std::isfinite(high))
      fail(high_name, high, unit, std::string("> ") + low_name + " = " + number(low) + " " + unit);
  };
  positive(p.stiffness, "stiffness", "N/m");
  positive(p.damping, "damping", "N·s/m");
  nonNegative(p.rotational_stiffness, "rotational_stiffness", "N·m/rad");
  nonNegative(p.rotational_damping, "rotational_damping", "N·m·s/rad");
  positive(p.compensation_time, "compensation_time", "s");
  band(p.error_low, p.error_high, "error_low", "error_high", "m");
  band(p.rest_low, p.rest_high, "rest_low", "rest_high", "m");
  band(p.rotation_error_low, p.rotation_error_high, "rotation_error_low", "rotation_error_high", "rad");
  band(p.rotation_rest_low, p.rotation_rest_high, "rotation_rest_low", "rotation_rest_high", "rad");
}

void TransparencyLayer::engage(double time, const KDL::Frame& master, const KDL::Frame& slave) noexcept {
  engaged_ = true;
  full_ = false;
  start_ = time;
  offset_ = vector(master.p - slave.p);
  rest_ = offset_;
  // φ_L = log(R_sᵀ R_m), slave axes; without a rotational spring there is nothing to compensate.
  rotation_offset_ = p_.rotational_stiffness > 0.0 ? vector((slave.M.Inverse() * master.M).GetRot()) : Vector3::Zero();
  rest_rotation_ = rotation_offset_;
  alpha_ = 0.0;
}

void TransparencyLayer::compute(double time, const KDL::Frame& master, const Vector6& master_twist,
                                const KDL::Frame& slave, const Vector6& slave_twist, Vector6& master_wrench,
                                Vector6& slave_wrench) noexcept {
  if (!engaged_) {
    master_wrench.setZero();
    slave_wrench.setZero();
    return;
  }
  const double fall = smoothFall((time - start_) / p_.compensation_time);  // 1 at t_s, 0 from t_s + t_c
  rest_ = offset_ * fall;                                                  // l(t)
  rest_rotation_ = rotation_offset_ * fall;                                // φ_l(t)
  const Vector3 error = vector(master.p - slave.p);
  const bool rotation = p_.rotational_stiffness > 0.0;
  // e_r: from the slave's rotation carried by the rest rotation to the master's, base axes, rad.
  const Vector3 rotation_error = rotation ? vector(KDL::diff(slave.M * exp(rest_rotation_), master.M)) : Vector3::Zero();
  if (!full_) {
    alpha_ = weight(error.norm(), p_.error_low, p_.error_high) * weight(rest_.norm(), p_.rest_low, p_.rest_high);
    if (rotation)
      alpha_ *= weight(vector((slave.M.Inverse() * master.M).GetRot()).norm(), p_.rotation_error_low,
                       p_.rotation_error_high) *
                weight(rest_rotation_.norm(), p_.rotation_rest_low, p_.rotation_rest_high);
    if (alpha_ >= 1.0) full_ = true;  // t_M: from now on alpha = 1 (eq. 4.16)
  }
  if (full_) alpha_ = 1.0;
  const Vector6 relative = master_twist - slave_twist;
  Vector6 coupling;
  coupling.head<3>() = p_.stiffness * (error - rest_) + p_.damping * relative.head<3>();
  coupling.tail<3>() = p_.rotational_stiffness * rotation_error + p_.rotational_damping * relative.tail<3>();
  master_wrench = -coupling;
  slave_wrench = alpha_ * coupling;
}

PassivityLayer::PassivityLayer(const PassivityParameters& p) : p_(p) {
  requireLevels(p.master, "master");
  requireLevels(p.slave, "slave");
  if (!(p.master_max_force >= 0.0))
    throw std::invalid_argument("PassivityLayer: master_max_force = " + number(p.master_max_force) +
                                " N: must be >= 0 (the force the master device renders)");
  if (!(p.master_max_torque >= 0.0))
    throw std::invalid_argument("PassivityLayer: master_max_torque = " + number(p.master_max_torque) +
                                " N·m: must be >= 0 (the torque the master device renders)");
  if (!(p.transfer_power > 0.0) || !std::isfinite(p.transfer_power))
    throw std::invalid_argument("PassivityLayer: transfer_power = " + number(p.transfer_power) +
                                " W: must be > 0 (P̄, the rate of the exchange between the tanks)");
  master_ = p.master.initial;
  slave_ = p.slave.initial;
}

PassivityStep PassivityLayer::step(double dt, const Vector6& master_desired, const Vector6& slave_desired,
                                   const Vector6& master_twist, const Vector6& slave_twist,
                                   double master_dissipation, double slave_dissipation) noexcept {
  PassivityStep out;
  if (!(dt > 0.0)) return out;
  const TankLevels& lm = p_.master;
  const TankLevels& ls = p_.slave;
  const double sigma_m = master_ <= lm.maximum ? 1.0 : 0.0;  // eq. 4.7 per tank
  const double sigma_s = slave_ <= ls.maximum ? 1.0 : 0.0;
  // A dissipation that is not a finite power >= 0 (a NaN from a sensor) adds nothing.
  const auto power = [](double w) { return std::isfinite(w) && w > 0.0 ? w : 0.0; };
  const double dm = power(master_dissipation) * dt, ds = power(slave_dissipation) * dt;
  if (!std::isfinite(dm) || !std::isfinite(ds)) return out;  // dt = inf: nothing is paid or moved
  // Eq. 4.21-4.23: a full tank passes its dissipation on; a rich tank feeds one that asks, at P̄,
  // never below its own ε (a long period could otherwise move more than T_ava - ε).
  const double request_m = master_ < lm.request ? 1.0 : 0.0, request_s = slave_ < ls.request ? 1.0 : 0.0;
  const double give_m = master_ >= lm.available ? 1.0 : 0.0, give_s = slave_ >= ls.available ? 1.0 : 0.0;
  const double transfer_m = std::min(p_.transfer_power * dt, std::max(master_ - lm.minimum, 0.0));
  const double transfer_s = std::min(p_.transfer_power * dt, std::max(slave_ - ls.minimum, 0.0));
  const double out_m = (1.0 - sigma_m) * dm + request_s * give_m * transfer_m;
  const double out_s = (1.0 - sigma_s) * ds + request_m * give_s * transfer_s;
  double master_next = master_ + sigma_m * dm + sigma_m * out_s - out_m;
  double slave_next = slave_ + sigma_s * ds + sigma_s * out_m - out_s;
  spilled_ += (1.0 - sigma_m) * out_s + (1.0 - sigma_s) * out_m;
  // The master wrench the device can render: force and torque each cut to their limit, keeping
  // their direction (a limit of 0 renders none).
  Vector6 rendered = master_desired;
  const auto cut = [](auto part, double limit) {
    const double norm = part.norm();
    if (norm > limit) part *= limit > 0.0 ? limit / norm : 0.0;
  };
  cut(rendered.head<3>(), p_.master_max_force);
  cut(rendered.tail<3>(), p_.master_max_torque);
  out.master_limited = !payForWrench(rendered, master_twist, dt, lm.minimum, master_next, out.master_wrench);
  out.slave_limited = !payForWrench(slave_desired, slave_twist, dt, ls.minimum, slave_next, out.slave_wrench);
  master_ = master_next;
  slave_ = slave_next;
  return out;
}

}  // namespace cobra::control
