#pragma once
// `cobra describe`: the reverse of the thesis' OroEdit feature — explores a deployment and
// writes every instance, activity, peer and connection as reusable Configurator tables (Lua).

#include <string>

#include "cobra/deploy/configurator.hpp"

namespace cobra::tools {

/// Lua source defining packages_list, components_list, activities_list, peers_list and
/// connections_list for what `configurator` has deployed, followed by the Configurator calls
/// that rebuild it. Connections to ports outside the deployment are left out (and counted in a
/// comment).
std::string describeDeployment(const deploy::Configurator& configurator, const std::string& origin);

}  // namespace cobra::tools
