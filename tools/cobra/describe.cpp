#include "describe.hpp"

#include "cobra/deploy/description.hpp"

namespace cobra::tools {

// The policy tables (with the transport, topic and qos of connections between hosts) are written
// by deploy::luaPolicyTable (deploy/src/description_lua.cpp), the seam for every connection entry.
std::string describeDeployment(const deploy::Configurator& configurator) {
  return deploy::toLua(deploy::describe(configurator));
}

}  // namespace cobra::tools
