#include "cobra/control/teleoperation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
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

/// The tank's levels, named as the PassivityLayer component's properties: `prefix` + minimum, ...
/// (prefix "master_" for the co-located layer's master tank, "" for one side's component).
void requireLevels(const TankLevels& t, const std::string& prefix) {
  auto fail = [&](const char* level, double value, const std::string& rule) {
    throw std::invalid_argument("PassivityLayer: " + prefix + level + " = " + number(value) + " J: must be " + rule +
                                " (0 < minimum < request < available < maximum, minimum < initial <= maximum)");
  };
  if (!(t.minimum > 0.0) || !std::isfinite(t.minimum)) fail("minimum", t.minimum, "> 0");
  if (!(t.request > t.minimum)) fail("request", t.request, "> " + prefix + "minimum = " + number(t.minimum) + " J");
  if (!(t.available > t.request))
    fail("available", t.available, "> " + prefix + "request = " + number(t.request) + " J");
  if (!(t.maximum > t.available) || !std::isfinite(t.maximum))
    fail("maximum", t.maximum, "> " + prefix + "available = " + number(t.available) + " J");
  if (!(t.initial > t.minimum && t.initial <= t.maximum))
    fail("initial", t.initial,
         "in (" + prefix + "minimum, " + prefix + "maximum] = (" + number(t.minimum) + ", " + number(t.maximum) + "] J");
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

PassivitySide::PassivitySide(const PassivitySideParameters& p, const std::string& name) : p_(p) {
  const std::string prefix = name.empty() ? "" : name + "_";
  const std::string device = name.empty() ? "its robot" : "the " + name + " device";
  requireLevels(p.tank, prefix);
  if (!(p.max_force >= 0.0))
    throw std::invalid_argument("PassivityLayer: " + prefix + "max_force = " + number(p.max_force) +
                                " N: must be >= 0 (the force " + device + " renders)");
  if (!(p.max_torque >= 0.0))
    throw std::invalid_argument("PassivityLayer: " + prefix + "max_torque = " + number(p.max_torque) +
                                " N·m: must be >= 0 (the torque " + device + " renders)");
  if (!(p.transfer_power > 0.0) || !std::isfinite(p.transfer_power))
    throw std::invalid_argument("PassivityLayer: transfer_power = " + number(p.transfer_power) +
                                " W: must be > 0 (P̄, the rate of the exchange between the tanks)");
  energy_ = p.tank.initial;
}

void PassivitySide::receive(const EnergyPacket& packet) noexcept {
  peer_request_ = packet.request;
  if (!(packet.energy > 0.0) || !std::isfinite(packet.energy)) return;
  received_ += packet.energy;
  if (energy_ <= p_.tank.maximum) {
    energy_ += packet.energy;  // eq. 4.7: σ = 1
  } else {
    spilled_ += packet.energy;
  }
}

PassivitySideStep PassivitySide::step(double dt, const Vector6& desired, const Vector6& twist,
                                      double dissipation) noexcept {
  PassivitySideStep out;
  out.packet.request = requesting();
  if (!(dt > 0.0) || !std::isfinite(dt)) return out;  // nothing is paid or moved
  const TankLevels& l = p_.tank;
  // A dissipation that is not a finite power >= 0 (a NaN from a sensor) adds nothing.
  const double d = std::isfinite(dissipation) && dissipation > 0.0 ? dissipation * dt : 0.0;
  if (!std::isfinite(d)) return out;  // a finite power over a finite period that overflows
  // Settle the last period: its wrench did F·t_end·dt if the robot's step moved with the twist at
  // its end; the tank paid F·t_start·dt. The excess (never a refund: an explicit step did the
  // latter) is paid now. A twist that is not finite settles nothing (there is no measurement).
  const double excess = p_.settle ? last_wrench_.dot(twist - last_twist_) * last_dt_ : 0.0;
  if (std::isfinite(excess) && excess > 0.0) {
    energy_ -= excess;
    paid_ += excess;
  }
  last_wrench_.setZero();
  last_dt_ = 0.0;
  // Eq. 4.19: the tank stores the robot's dissipation while at most T̄ (σ = 1), else passes it on.
  credited_ += d;
  double packet = 0.0;
  if (energy_ <= l.maximum) {
    energy_ += d;
  } else {
    packet += d;
  }
  // Eq. 4.21-4.23: a rich tank feeds one that asks, at P̄, never below its own ε (a long period
  // could otherwise move more than T_ava - ε).
  if (peer_request_ && energy_ >= l.available) {
    const double give = std::min(p_.transfer_power * dt, std::max(energy_ - l.minimum, 0.0));
    energy_ -= give;
    packet += give;
  }
  sent_ += packet;
  out.packet.energy = packet;
  // The wrench the robot can render: force and torque each cut to their limit, keeping their
  // direction (a limit of 0 renders none).
  Vector6 rendered = desired;
  const auto cut = [](auto part, double limit) {
    const double norm = part.norm();
    if (norm > limit) part *= limit > 0.0 ? limit / norm : 0.0;
  };
  cut(rendered.head<3>(), p_.max_force);
  cut(rendered.tail<3>(), p_.max_torque);
  const double before = energy_;
  // A tank a settlement took below ε implements nothing, not even a wrench that would pay it
  // (its own settlement could take more): the undershoot stays one period's excess.
  out.limited = energy_ < l.minimum ? !rendered.isZero(0.0)
                                    : !payForWrench(rendered, twist, dt, l.minimum, energy_, out.wrench);
  paid_ += before - energy_;
  if (!out.limited) {
    last_wrench_ = out.wrench;
    last_twist_ = twist;
    last_dt_ = dt;
  }
  out.packet.request = requesting();
  return out;
}

namespace {
PassivitySideParameters side(const TankLevels& tank, double transfer_power, double max_force, double max_torque) {
  return PassivitySideParameters{tank, transfer_power, max_force, max_torque};
}
}  // namespace

PassivityLayer::PassivityLayer(const PassivityParameters& p)
    : master_(side(p.master, p.transfer_power, p.master_max_force, p.master_max_torque), "master"),
      slave_(side(p.slave, p.transfer_power, std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()),
             "slave") {
  // Each knows from the start whether the other asks, as the next packets will tell.
  master_.receive(EnergyPacket{0.0, slave_.requesting()});
  slave_.receive(EnergyPacket{0.0, master_.requesting()});
}

PassivityStep PassivityLayer::step(double dt, const Vector6& master_desired, const Vector6& slave_desired,
                                   const Vector6& master_twist, const Vector6& slave_twist,
                                   double master_dissipation, double slave_dissipation) noexcept {
  const PassivitySideStep m = master_.step(dt, master_desired, master_twist, master_dissipation);
  const PassivitySideStep s = slave_.step(dt, slave_desired, slave_twist, slave_dissipation);
  master_.receive(s.packet);  // no link: the packets arrive in the same step
  slave_.receive(m.packet);
  PassivityStep out;
  out.master_wrench = m.wrench;
  out.slave_wrench = s.wrench;
  out.master_limited = m.limited;
  out.slave_limited = s.limited;
  return out;
}

}  // namespace cobra::control
