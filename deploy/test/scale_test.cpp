// Deploys 1,000 components with 10 ports each and measures the memory of an unconnected port.
// Timings are printed, not asserted (ARCHITECTURE §8: timings live in bench/).

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/configurator.hpp"
#include "cobra/test_support/counting_new.hpp"


using namespace cobra;
using namespace std::chrono_literals;

namespace {

constexpr int kComponents = 1000;
constexpr int kPairs = 5;  // 5 inputs + 5 outputs = 10 ports per component

/// A Calculation with 5 inputs and 5 outputs: out_i = in_i + 1 on every new sample.
class TenPorts : public core::Component {
 public:
  explicit TenPorts(std::string name) : Component(std::move(name), core::Role::Calculation, "5 in, 5 out") {
    for (auto& port : inputs_) addEventPort(port);
    for (auto& port : outputs_) addPort(port);
  }

 protected:
  void updateHook() override {
    for (int i = 0; i < kPairs; ++i) {
      double value = 0.0;
      while (inputs_[static_cast<std::size_t>(i)].read(value) == core::FlowStatus::NewData)
        outputs_[static_cast<std::size_t>(i)].write(value + 1.0);
    }
  }

 private:
  std::array<core::InputPort<double>, kPairs> inputs_{
      core::InputPort<double>{"in0", "joint position set-point, axis 0", "rad"},
      core::InputPort<double>{"in1", "joint position set-point, axis 1", "rad"},
      core::InputPort<double>{"in2", "joint position set-point, axis 2", "rad"},
      core::InputPort<double>{"in3", "joint position set-point, axis 3", "rad"},
      core::InputPort<double>{"in4", "joint position set-point, axis 4", "rad"}};
  std::array<core::OutputPort<double>, kPairs> outputs_{
      core::OutputPort<double>{"out0", "filtered joint position, axis 0", "rad"},
      core::OutputPort<double>{"out1", "filtered joint position, axis 1", "rad"},
      core::OutputPort<double>{"out2", "filtered joint position, axis 2", "rad"},
      core::OutputPort<double>{"out3", "filtered joint position, axis 3", "rad"},
      core::OutputPort<double>{"out4", "filtered joint position, axis 4", "rad"}};
};

/// The same component without its 10 ports: the baseline for the per-port figures.
class NoPorts : public core::Component {
 public:
  explicit NoPorts(std::string name) : Component(std::move(name), core::Role::Calculation, "5 in, 5 out") {}
};

std::string instance(int i) {
  char name[16];
  std::snprintf(name, sizeof name, "C%04d", i);
  return name;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

TEST(Scale, UnconnectedPortCostsLessThanOneKibibyte) {
  const std::size_t before_ten = cobra::test_support::newBytes();
  auto ten = std::make_unique<TenPorts>("Ten");
  const std::size_t heap_ten = cobra::test_support::newBytes() - before_ten - sizeof(TenPorts);
  const std::size_t before_none = cobra::test_support::newBytes();
  auto none = std::make_unique<NoPorts>("None");
  const std::size_t heap_none = cobra::test_support::newBytes() - before_none - sizeof(NoPorts);

  const double per_port_object = static_cast<double>(sizeof(TenPorts) - sizeof(NoPorts)) / (2 * kPairs);
  const double per_port_heap = static_cast<double>(heap_ten - heap_none) / (2 * kPairs);
  std::printf("sizeof(InputPort<double>) = %zu B, sizeof(OutputPort<double>) = %zu B, sizeof(Component) = %zu B\n",
              sizeof(core::InputPort<double>), sizeof(core::OutputPort<double>), sizeof(core::Component));
  std::printf("per unconnected port: %.1f B in the component object + %.1f B of heap = %.1f B\n", per_port_object,
              per_port_heap, per_port_object + per_port_heap);
  EXPECT_LT(per_port_object + per_port_heap, 1024.0);
}

TEST(Scale, ThousandComponentsWithTenPortsDeployConnectAndRun) {
  deploy::Configurator configurator;
  components::addBuiltinPackages(configurator.packages());
  configurator.packages().addBuiltin("scale", [](deploy::PackageBuilder& p) { p.component<TenPorts>("TenPorts", "5 in, 5 out"); });
  std::vector<deploy::ComponentSpec> components;
  std::vector<deploy::ActivitySpec> activities;
  std::vector<deploy::ConnectionSpec> connections;
  std::vector<deploy::NameEntry> lifecycle;
  for (int i = 0; i < kComponents; ++i) {
    const deploy::SourceLocation where{"scale.lua", i + 1};
    components.push_back({instance(i), "TenPorts", where});
    activities.push_back({instance(i), i == 0 ? 0.001 : 0.0, 0, "ORO_SCHED_OTHER", where});
    lifecycle.push_back({instance(i), where});
    for (int p = 0; i + 1 < kComponents && p < kPairs; ++p)
      connections.push_back({instance(i) + ".out" + std::to_string(p), instance(i + 1) + ".in" + std::to_string(p),
                             {"buffer", 4}, where});
  }

  const auto start = std::chrono::steady_clock::now();
  const std::size_t heap_before = cobra::test_support::newBytes();
  configurator.initConfigurator({{"scale", {"scale.lua", 0}}}, components);
  configurator.setActivities(activities);
  const double created = secondsSince(start);
  const auto connect_start = std::chrono::steady_clock::now();
  const std::size_t heap_before_connect = cobra::test_support::newBytes();
  EXPECT_TRUE(configurator.connectPorts(connections).empty());
  const double connected = secondsSince(connect_start);
  const std::size_t heap_connections = cobra::test_support::newBytes() - heap_before_connect;
  configurator.configureComponents(lifecycle);
  configurator.startComponents(lifecycle);
  const double total = secondsSince(start);
  std::printf("%d components x %d ports, %zu connections: created + activities %.3f s, connected %.3f s, "
              "deployed in total %.3f s; %.1f MB allocated (connections: %.0f B each, buffer(4) of double)\n",
              kComponents, 2 * kPairs, connections.size(), created, connected, total,
              static_cast<double>(cobra::test_support::newBytes() - heap_before) / 1e6,
              static_cast<double>(heap_connections) / static_cast<double>(connections.size()));

  // Data crosses all 1,000 components in the instant it is written.
  auto& first = configurator.getReferences().get(instance(0));
  core::InputPort<double> probe{"probe", "end of the chain", "rad"};
  core::connectPorts(configurator.getReferences().get(instance(kComponents - 1)).port("out3"), probe,
                     core::ConnPolicy::buffer(4));
  core::OutputPort<double> source{"source", "start of the chain", "rad"};
  core::connectPorts(source, first.port("in3"), core::ConnPolicy::buffer(4));
  source.write(0.5);
  configurator.clock().advance(1ms);
  double value = 0.0;
  ASSERT_EQ(probe.read(value), core::FlowStatus::NewData);
  EXPECT_DOUBLE_EQ(value, 0.5 + kComponents);
  EXPECT_EQ(configurator.getReferences().get(instance(kComponents - 1)).updateCount(), 1u);
}
