#include "cobra/components/control/package.hpp"

#include "cobra/components/control/link_impairment_component.hpp"
#include "cobra/components/control/teleoperation_clutch.hpp"
#include "cobra/components/control/teleoperation_components.hpp"
#include "cobra/components/control/variable_admittance_component.hpp"

namespace cobra::components {

void registerControlPackage(deploy::PackageBuilder& package) {
  package.component<VariableAdmittanceController>("VariableAdmittance", "tank-based variable admittance (thesis §4.5.3)")
      .component<TransparencyLayerComponent>("TransparencyLayer", "teleoperation coupling forces (thesis §4.5.4)")
      .component<PassivityLayerComponent>("PassivityLayer", "one side's teleoperation force paid by its energy tank (thesis §4.5.4)")
      .component<LinkImpairmentComponent>("LinkImpairment", "delay, jitter and loss on a teleoperation link (thesis §4.5.4)")
      .component<TeleoperationClutch>("TeleoperationClutch",
                                      "the tool follows the haptic device's motion from the teleoperation's start (§5.5)");
}

}  // namespace cobra::components
