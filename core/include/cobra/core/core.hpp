#pragma once
/// @file
/// Everything of the cobra runtime in one include.

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"
#include "cobra/core/conn_policy.hpp"
#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"
#include "cobra/core/event.hpp"
#include "cobra/core/introspection.hpp"
#include "cobra/core/lockstep_clock.hpp"
#include "cobra/core/port.hpp"
#include "cobra/core/property.hpp"
#include "cobra/core/transport.hpp"
