#pragma once
// `cobra describe`: the reverse of the thesis' OroEdit feature — explores a deployment and
// writes every instance, property value, activity, peer, connection, named deployment and
// configuration as reusable Configurator tables (Lua), through deploy/description.hpp's writer.

#include <string>

#include "cobra/deploy/configurator.hpp"

namespace cobra::tools {

/// The Lua deployment file of what `configurator` has deployed (deploy::describe, then
/// deploy::toLua). Connections to ports outside the deployment are left out (and counted in a
/// comment).
std::string describeDeployment(const deploy::Configurator& configurator);

}  // namespace cobra::tools
