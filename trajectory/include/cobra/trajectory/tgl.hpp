#pragma once
/// @file
/// Everything of cobra::trajectory, the thesis' Trajectory Generation Library (TGL, §3.2.3).

#include "cobra/trajectory/cartesian.hpp"
#include "cobra/trajectory/cartesian_stop.hpp"
#include "cobra/trajectory/conditions.hpp"
#include "cobra/trajectory/multi_axis.hpp"
#include "cobra/trajectory/multi_point.hpp"
#include "cobra/trajectory/polynomial.hpp"
#include "cobra/trajectory/trajectory.hpp"
