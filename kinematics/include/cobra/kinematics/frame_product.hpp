#pragma once
/// @file
/// KDL's rotation and frame products written out inline, in KDL's own order of operations (the
/// same bits: serial_chain_test compares them). KDL defines Rotation * Rotation out of line in its
/// shared library, so every frame product in a 1 kHz loop paid a call the compiler could not see
/// through; forward kinematics, the simulated robots and the monitors compose many per step.

#include <kdl/frames.hpp>

namespace cobra::kinematics {

/// a * b, bit-identical to KDL's operator*(const Rotation&, const Rotation&).
inline KDL::Rotation rotationProduct(const KDL::Rotation& a, const KDL::Rotation& b) noexcept {
  const double* l = a.data;
  const double* r = b.data;
  return KDL::Rotation(l[0] * r[0] + l[1] * r[3] + l[2] * r[6], l[0] * r[1] + l[1] * r[4] + l[2] * r[7],
                       l[0] * r[2] + l[1] * r[5] + l[2] * r[8], l[3] * r[0] + l[4] * r[3] + l[5] * r[6],
                       l[3] * r[1] + l[4] * r[4] + l[5] * r[7], l[3] * r[2] + l[4] * r[5] + l[5] * r[8],
                       l[6] * r[0] + l[7] * r[3] + l[8] * r[6], l[6] * r[1] + l[7] * r[4] + l[8] * r[7],
                       l[6] * r[2] + l[7] * r[5] + l[8] * r[8]);
}

/// a * b, bit-identical to KDL's operator*(const Frame&, const Frame&).
inline KDL::Frame frameProduct(const KDL::Frame& a, const KDL::Frame& b) noexcept {
  return KDL::Frame(rotationProduct(a.M, b.M), a.M * b.p + a.p);
}

}  // namespace cobra::kinematics
