// Deployment cost (the thesis warns that many ports cost memory): creating 1,000
// components with 10 ports each through the Configurator, and connecting them in a chain
// (4,995 buffer(4) connections), plus the size of one unconnected port. The peer for the
// timing is the same work done by hand on core objects, without the Configurator's checks,
// undo journal and name lookups, so the table shows what the deployer's safety costs.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <vector>

#include "cobra/core/core.hpp"
#include "cobra/deploy/configurator.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra;

constexpr int kComponents = 1000;
constexpr int kPairs = 5;  // 5 inputs + 5 outputs = 10 ports per component

using cobra::bench::maxOf;

class TenPorts : public core::Component {
 public:
  explicit TenPorts(std::string name) : Component(std::move(name), core::Role::Calculation, "5 in, 5 out") {
    for (auto& port : inputs_) addEventPort(port);
    for (auto& port : outputs_) addPort(port);
  }

 private:
  std::array<core::InputPort<double>, kPairs> inputs_{
      core::InputPort<double>{"in0", "", "rad"}, core::InputPort<double>{"in1", "", "rad"},
      core::InputPort<double>{"in2", "", "rad"}, core::InputPort<double>{"in3", "", "rad"},
      core::InputPort<double>{"in4", "", "rad"}};
  std::array<core::OutputPort<double>, kPairs> outputs_{
      core::OutputPort<double>{"out0", "", "rad"}, core::OutputPort<double>{"out1", "", "rad"},
      core::OutputPort<double>{"out2", "", "rad"}, core::OutputPort<double>{"out3", "", "rad"},
      core::OutputPort<double>{"out4", "", "rad"}};
};

std::string instance(int i) {
  char name[16];
  std::snprintf(name, sizeof name, "C%04d", i);
  return name;
}

void BM_Configurator1000x10(benchmark::State& state) {
  std::vector<deploy::ComponentSpec> components;
  std::vector<deploy::ConnectionSpec> connections;
  for (int i = 0; i < kComponents; ++i) {
    const deploy::SourceLocation where{"scale.lua", i + 1};
    components.push_back({instance(i), "TenPorts", where});
    for (int p = 0; i + 1 < kComponents && p < kPairs; ++p)
      connections.push_back({instance(i) + ".out" + std::to_string(p), instance(i + 1) + ".in" + std::to_string(p),
                             {"buffer", 4}, where});
  }
  for (auto _ : state) {
    auto configurator = std::make_unique<deploy::Configurator>();
    configurator->packages().addBuiltin("scale",
                                        [](deploy::PackageBuilder& p) { p.component<TenPorts>("TenPorts", "10 ports"); });
    configurator->initConfigurator({{"scale", {"scale.lua", 0}}}, components);
    benchmark::DoNotOptimize(configurator->connectPorts(connections));
    state.PauseTiming();  // tearing down is not deploying
    configurator.reset();
    state.ResumeTiming();
  }
  state.counters["connections"] = static_cast<double>(connections.size());
}

void BM_ByHand1000x10(benchmark::State& state) {
  for (auto _ : state) {
    std::vector<std::unique_ptr<TenPorts>> components;
    components.reserve(kComponents);
    for (int i = 0; i < kComponents; ++i) components.push_back(std::make_unique<TenPorts>(instance(i)));
    for (int i = 0; i + 1 < kComponents; ++i)
      for (int p = 0; p < kPairs; ++p)
        core::connectPorts(components[i]->port("out" + std::to_string(p)), components[i + 1]->port("in" + std::to_string(p)),
                           core::ConnPolicy::buffer(4));
    state.PauseTiming();
    components.clear();
    state.ResumeTiming();
  }
}

void BM_UnconnectedPortSize(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(sizeof(core::InputPort<double>));
  state.counters["input_port_bytes"] = sizeof(core::InputPort<double>);
  state.counters["output_port_bytes"] = sizeof(core::OutputPort<double>);
}

BENCHMARK(BM_Configurator1000x10)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5)
    ->ComputeStatistics("max", maxOf)->ReportAggregatesOnly(true);
BENCHMARK(BM_ByHand1000x10)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5)
    ->ComputeStatistics("max", maxOf)->ReportAggregatesOnly(true);
BENCHMARK(BM_UnconnectedPortSize)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
