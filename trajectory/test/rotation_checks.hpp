#pragma once
// Rotation measures shared by the Cartesian tests, accurate at small angles (KDL's GetRot and
// GetRotAngle round rotations below about 1e-3 rad to zero, too coarse for derivative checks).

#include <algorithm>
#include <cmath>

#include <kdl/frames.hpp>

namespace cobra::trajectory::test {

/// vee((R - R^T) / 2) = sin(angle) axis: the rotation vector of a small rotation.
inline KDL::Vector smallRotationVector(const KDL::Rotation& r) {
  return KDL::Vector(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1)) / 2.0;
}

/// Geodesic distance on SO(3) between a and b (rad).
inline double angleBetween(const KDL::Rotation& a, const KDL::Rotation& b) {
  const KDL::Rotation r = a.Inverse() * b;
  return std::atan2(smallRotationVector(r).Norm(), (r(0, 0) + r(1, 1) + r(2, 2) - 1.0) / 2.0);
}

/// How far `r` is from a rotation: max of |R^T R - I| over the entries and |det R - 1|.
inline double rotationError(const KDL::Rotation& r) {
  double error = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (int m = 0; m < 3; ++m) dot += r(m, i) * r(m, j);
      error = std::max(error, std::abs(dot - (i == j ? 1.0 : 0.0)));
    }
  const double det = KDL::dot(r.UnitX() * r.UnitY(), r.UnitZ());
  return std::max(error, std::abs(det - 1.0));
}

}  // namespace cobra::trajectory::test
