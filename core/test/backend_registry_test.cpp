// BackendRegistry: instances by full name, factories by scheme, registrations that end with their
// owner, one table per interface, and the messages of every refusal (they list what exists).

#include "cobra/core/backend_registry.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::core::BackendRegistry;
using cobra::test_support::messageOf;

class Pump {
 public:
  static constexpr const char* kBackendKind = "test pump";
  virtual ~Pump() = default;
  virtual std::string id() const = 0;
};

class Valve {
 public:
  static constexpr const char* kBackendKind = "test valve";
  virtual ~Valve() = default;
};

class NamedPump final : public Pump {
 public:
  explicit NamedPump(std::string id) : id_(std::move(id)) {}
  std::string id() const override { return id_; }

 private:
  std::string id_;
};

TEST(BackendRegistry, InstancesAreFoundByNameUntilTheirRegistrationEnds) {
  auto pump = std::make_shared<NamedPump>("simulated");
  {
    auto registration = BackendRegistry<Pump>::addInstance("sim:PumpSim", "simulated pump", pump);
    EXPECT_EQ(BackendRegistry<Pump>::open("sim:PumpSim").get(), pump.get());
    EXPECT_EQ(BackendRegistry<Pump>::names(), (std::vector<std::string>{"sim:PumpSim"}));
    EXPECT_EQ(messageOf([&] { auto again = BackendRegistry<Pump>::addInstance("sim:PumpSim", "other", pump); }),
              "a test pump backend named 'sim:PumpSim' exists already (simulated pump); backend names are unique in a "
              "process: give the device's component another name");
    EXPECT_TRUE(BackendRegistry<Valve>::names().empty());  // one table per interface
  }
  EXPECT_TRUE(BackendRegistry<Pump>::names().empty());
  EXPECT_CONTAINS(messageOf([] { BackendRegistry<Pump>::open("sim:PumpSim"); }),
                  "no test pump backend 'sim:PumpSim'; backends that exist: none (a sim-world component registers its "
                  "device as sim:<component name> when it is configured");
}

TEST(BackendRegistry, FactoriesMakeADeviceFromTheAddressAndTheirFailuresAreNamed) {
  BackendRegistry<Pump>::addFactory("serial", "a pump on a serial line", "package 'pumps'",
                                    [](const std::string& address) -> std::unique_ptr<Pump> {
                                      if (address == "missing") throw std::runtime_error("no such port");
                                      return std::make_unique<NamedPump>(address);
                                    });
  EXPECT_EQ(BackendRegistry<Pump>::open("serial:ttyS0")->id(), "ttyS0");
  EXPECT_EQ(messageOf([] { BackendRegistry<Pump>::open("serial:missing"); }),
            "test pump backend 'serial:missing': no such port");
  // The same owner again replaces its factory (a second Configurator loading the package).
  BackendRegistry<Pump>::addFactory("serial", "a pump on a serial line", "package 'pumps'",
                                    [](const std::string&) { return std::make_unique<NamedPump>("second"); });
  EXPECT_EQ(BackendRegistry<Pump>::open("serial:ttyS0")->id(), "second");
  EXPECT_EQ(messageOf([] {
              BackendRegistry<Pump>::addFactory("serial", "", "package 'other'",
                                                [](const std::string&) { return std::unique_ptr<Pump>(); });
            }),
            "package 'other' registers the test pump backend scheme 'serial', which package 'pumps' registered "
            "already; scheme names must be unique");

  auto registration = BackendRegistry<Pump>::addInstance("sim:P1", "simulated pump of component 'P1'",
                                                         std::make_shared<NamedPump>("p1"));
  EXPECT_EQ(BackendRegistry<Pump>::names(), (std::vector<std::string>{"serial:<address>", "sim:P1"}));
  const std::string listing =
      "backends that exist: 'serial:<address>' (a pump on a serial line, from package 'pumps'), 'sim:P1' (simulated "
      "pump of component 'P1')";
  EXPECT_CONTAINS(messageOf([] { BackendRegistry<Pump>::open("sim:P2"); }),
                  "no test pump backend 'sim:P2'; " + listing);
  EXPECT_CONTAINS(messageOf([] { BackendRegistry<Pump>::open("usb:1"); }), "no test pump backend 'usb:1'; " + listing);
  EXPECT_CONTAINS(messageOf([] { BackendRegistry<Pump>::open("sim"); }),
                  "'sim' is not a test pump backend name: expected <scheme>:<address>; " + listing);
}

TEST(BackendRegistry, MalformedNamesAreRefused) {
  auto pump = std::make_shared<NamedPump>("x");
  EXPECT_EQ(messageOf([&] { auto r = BackendRegistry<Pump>::addInstance("PumpSim", "", pump); }),
            "'PumpSim' is not a test pump backend name: expected <scheme>:<address>, e.g. sim:FTSensSim");
  EXPECT_EQ(messageOf([&] { auto r = BackendRegistry<Pump>::addInstance("sim:", "", pump); }),
            "'sim:' is not a test pump backend name: expected <scheme>:<address>, e.g. sim:FTSensSim");
  EXPECT_EQ(messageOf([] {
              BackendRegistry<Pump>::addFactory("us b", "", "package 'p'",
                                                [](const std::string&) { return std::unique_ptr<Pump>(); });
            }),
            "test pump backend scheme 'us b' (from package 'p'): expected letters, digits, '_' or '-', as in "
            "'socketcan'");
}

TEST(BackendRegistry, ARegistrationMovesAndResets) {
  cobra::core::BackendRegistration outer;
  {
    auto inner = BackendRegistry<Pump>::addInstance("sim:Moved", "moved", std::make_shared<NamedPump>("m"));
    outer = std::move(inner);
    EXPECT_FALSE(inner);
  }
  EXPECT_EQ(BackendRegistry<Pump>::open("sim:Moved")->id(), "m");
  outer.reset();
  EXPECT_FALSE(outer);
  EXPECT_CONTAINS(messageOf([] { BackendRegistry<Pump>::open("sim:Moved"); }), "no test pump backend 'sim:Moved'");
}

}  // namespace
