#pragma once
// The component packages built into the `cobra` program, beside "cobra_signal" (which the
// deployer always has): what a deployment file's packages_list can name without a shared library.

#include "cobra/deploy/configurator.hpp"

namespace cobra::tools {

/// Makes "cobra_motion", "cobra_coordination" and "cobra_control" loadable by `configurator`'s packages_list.
void addBuiltinPackages(deploy::Configurator& configurator);

}  // namespace cobra::tools
