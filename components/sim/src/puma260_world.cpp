#include "cobra/components/sim/puma260_world.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cobra::components {

Puma260World::Puma260World(std::string name)
    : SimulatedPuma260Base(std::move(name),
                           "the Puma 260 world in MuJoCo (thesis §6.4): arm, six CiA 402 drives on a simulated EtherCAT "
                           "bus, FTSens, contact tool and curved surface, for Puma260EtherCATMaster bus = sim:<name>") {
  for (core::PropertyBase* p : std::initializer_list<core::PropertyBase*>{&model_, &seed_, &encoder_noise_})
    addProperty(*p);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{&sensor_wrench_, &tool_pose_, &contact_force_,
                                                                  &penetration_, &true_position_})
    addPort(*p);
  true_position_.setDataSample(KDL::JntArray(6));
  addProperty(surface_cylinder_.readOnly());
  addOperation("surface", std::function<std::string()>([this] { return describeSurface(); }),
               "the curved surface: cylinder centre, axis, radius and length in the base frame (m)");
}

std::string Puma260World::describeSurface() const {
  if (arm_ == nullptr) return "not configured: no world";
  const sim::CylinderSurface& s = arm_->world().surface();
  char line[200];
  std::snprintf(line, sizeof line,
                "cylinder centre (%.4f, %.4f, %.4f) m, axis (%.4f, %.4f, %.4f), radius %.4f m, length %.4f m", s.centre.x(),
                s.centre.y(), s.centre.z(), s.axis.x(), s.axis.y(), s.axis.z(), s.radius, 2.0 * s.half_length);
  return line;
}

bool Puma260World::configureHook() {
  std::array<double, 6> initial{};
  if (!initialPosition(initial)) return false;
  if (model_().empty())
    return refuse("property model is empty: give the MJCF file of the world (e.g. apps/puma260/world/puma260.xml)");
  if (!(encoder_noise_() >= 0.0) || !std::isfinite(encoder_noise_()))
    return refuse("property encoder_noise = " + std::to_string(encoder_noise_()) +
                  " rad; expected >= 0 (a standard deviation)");
  try {
    auto arm = std::make_unique<sim::MujocoPuma260Arm>(model_(), sim::MujocoPuma260Arm::defaultDrives(), initial);
    sim::MujocoPuma260Arm* raw = arm.get();
    openBus("simulated Puma 260 drives on the MuJoCo world of component '" + name() + "'", std::move(arm))
        .setEncoderNoise(encoder_noise_(), static_cast<std::uint64_t>(seed_()));
    arm_ = raw;
    const sim::CylinderSurface& c = raw->world().surface();
    const KDL::Vector a = c.centre - c.axis * c.half_length, b = c.centre + c.axis * c.half_length;
    surface_cylinder_.setFromOwner({a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.radius});
  } catch (const std::invalid_argument& e) {
    SimulatedPuma260Base::cleanupHook();
    arm_ = nullptr;
    return refuse("property model: " + std::string(e.what()));
  }
  return true;
}

void Puma260World::cleanupHook() {
  arm_ = nullptr;
  SimulatedPuma260Base::cleanupHook();
}

void Puma260World::updateHook() {
  stepBus();
  const sim::MujocoPuma260World& world = arm_->world();
  for (int i = 0; i < 6; ++i) out_(static_cast<unsigned>(i)) = world.jointPosition(i);
  true_position_.write(out_);
  sensor_wrench_.write(world.sensorWrench());
  tool_pose_.write(world.toolPose());
  contact_force_.write(world.contactForce());
  penetration_.write(world.penetration());
}

}  // namespace cobra::components
