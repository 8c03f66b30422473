#include "cobra/components/sim/puma260_world.hpp"

#include <cstdio>
#include <stdexcept>

#include "cobra/core/activity.hpp"

namespace cobra::components {

Puma260World::Puma260World(std::string name)
    : Component(std::move(name), core::Role::Bridge,
                "the Puma 260 world in MuJoCo (thesis §6.4): arm, six CiA 402 drives on a simulated EtherCAT bus, "
                "FTSens, contact tool and curved surface, for Puma260EtherCATMaster bus = sim:<name>") {
  // Puma260EtherCATMaster's default nest (Corke's nominal pose qn, ASSUMPTION: the arm rests in its
  // nest, the encoder initialisation position, at power-on).
  initial_.set({0.0, 0.7853981633974483, -3.141592653589793, 0.0, 0.7853981633974483, 0.0});
  for (core::PropertyBase* p : std::initializer_list<core::PropertyBase*>{&model_, &initial_, &seed_, &encoder_noise_})
    addProperty(*p);
  for (core::PortBase* p : std::initializer_list<core::PortBase*>{&sensor_wrench_, &tool_pose_, &contact_force_,
                                                                  &penetration_, &true_position_})
    addPort(*p);
  true_position_.setDataSample(KDL::JntArray(6));
  addOperation("injectFault", &Puma260World::injectFault, this,
               "fault: an over-current fault in drive i (the drive goes to Fault, its brake holds the joint)")
      .arg("slave", "1", "slave index, 0-5");
  addOperation("injectWorkingCounterFault", &Puma260World::injectWorkingCounterFault, this,
               "fault: the next n bus cycles come back with a wrong working counter (the last slave skips its "
               "datagram)")
      .arg("cycles", "1", "number of bus cycles, >= 1");
  addOperation("surface", std::function<std::string()>([this] { return describeSurface(); }),
               "the curved surface: cylinder centre, axis, radius and length in the base frame (m)");
}

void Puma260World::injectFault(int slave) {
  if (arm_ == nullptr) throw std::invalid_argument("the simulated arm exists only while the component is configured");
  if (slave < 0 || slave > 5) throw std::invalid_argument("slave " + std::to_string(slave) + " is not 0-5");
  arm_->drive(slave).injectFault(sim::error_code::kOverCurrent);
}

void Puma260World::injectWorkingCounterFault(int cycles) {
  if (device_.get() == nullptr)
    throw std::invalid_argument("the simulated bus exists only while the component is configured");
  if (cycles < 1) throw std::invalid_argument("cycles = " + std::to_string(cycles) + ", expected >= 1");
  device_.get()->injectWorkingCounterFault(cycles);
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
  if (activity().period().count() <= 0) return refuse("needs a periodic activity: each update steps the world");
  if (model_().empty())
    return refuse("property model is empty: give the MJCF file of the world (e.g. apps/puma260/world/puma260.xml)");
  if (initial_().size() != 6)
    return refuse("property initial_position has " + std::to_string(initial_().size()) +
                  " numbers; give 6 joint angles in rad");
  std::array<double, 6> initial{};
  for (std::size_t i = 0; i < 6; ++i) initial[i] = initial_()[i];
  try {
    auto arm = std::make_unique<sim::MujocoPuma260Arm>(model_(), sim::Puma260ArmModel::defaults(), initial);
    sim::MujocoPuma260Arm* raw = arm.get();
    sim::Puma260EtherCatBus& bus = device_.open(
        *this, "simulated Puma 260 drives on the MuJoCo world of component '" + name() + "'",
        std::unique_ptr<sim::Puma260Plant>(std::move(arm)));
    bus.setEncoderNoise(encoder_noise_(), static_cast<std::uint64_t>(seed_()));
    arm_ = raw;
  } catch (const std::invalid_argument& e) {
    device_.close();
    arm_ = nullptr;
    return refuse("property model: " + std::string(e.what()));
  }
  return true;
}

bool Puma260World::startHook() {
  interval_.reset();
  return true;
}

void Puma260World::cleanupHook() {
  arm_ = nullptr;
  device_.close();
}

void Puma260World::updateHook() {
  sim::Puma260EtherCatBus& bus = *device_.get();
  bus.step(interval_.next(*this));
  const sim::MujocoPuma260World& world = arm_->world();
  for (int i = 0; i < 6; ++i) out_(static_cast<unsigned>(i)) = world.jointPosition(i);
  true_position_.write(out_);
  sensor_wrench_.write(world.sensorWrench());
  tool_pose_.write(world.toolPose());
  contact_force_.write(world.contactForce());
  penetration_.write(world.penetration());
}

}  // namespace cobra::components
