#pragma once
/// @file
/// Everything of the deployer: packages, the Configurator, named deployments and configurations,
/// and the role linter.

#include "cobra/deploy/configurator.hpp"
#include "cobra/deploy/deployment_set.hpp"
#include "cobra/deploy/lint.hpp"
#include "cobra/deploy/package_registry.hpp"
#include "cobra/deploy/spec.hpp"
