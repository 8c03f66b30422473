#pragma once
/// @file
/// What the simulated EtherCAT bus of the Puma 260 (puma260_ethercat_bus.hpp) drives: six CiA 402
/// drives on an arm that something integrates — the analytic sim::Puma260Arm (the drives' own
/// motor models plus gravity) or the MuJoCo world (sim::MujocoPuma260Arm: MuJoCo integrates the
/// arm, the drives only compute torque). Joint-side SI units (rad, rad/s, N·m).

#include "cobra/sim/cia402_drive.hpp"

namespace cobra::sim {

class Puma260Plant {
 public:
  static constexpr int kJoints = 6;
  virtual ~Puma260Plant() = default;
  /// Drive of `joint` (0-5): the bus writes its process data, tests inject faults.
  virtual Cia402Drive& drive(int joint) noexcept = 0;
  virtual const Cia402Drive& drive(int joint) const noexcept = 0;
  /// Advances the drives and the arm by `dt` s (> 0; anything else does nothing). Unpowered
  /// joints are held by their brakes. noexcept, no allocation, deterministic.
  virtual void step(double dt) noexcept = 0;
};

}  // namespace cobra::sim
