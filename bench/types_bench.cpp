// Cost of a type's capabilities (ARCHITECTURE §2, §8) for double, KDL.Frame and a record, each
// through its codec and, side by side in the same run, through the text form (DataTypeTraits
// print/parse), which is the path a type without codecs takes:
//  - Port: write then read on one thread through a `data` connection (typed), against writeText
//    then readText on the same ports (text).
//  - LuaProperty: a Lua value read by the type's Lua conversion and set on a Property (codec),
//    against a Lua string set with setFromText (text).
//  - CsvRow: one sample read by the Reporter's source and formatted into a CSV row (codec),
//    against the value printed and written as one text cell (text).
// Every benchmark runs 10 repetitions and reports their median and worst case ("max").

#include <benchmark/benchmark.h>

#include <algorithm>
#include <any>
#include <array>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <lua.hpp>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/core.hpp"
#include "cobra/core/record.hpp"
#include "cobra/script/convert.hpp"
#include "cobra/script/lua_state.hpp"
#include "cobra/types/register_type.hpp"
#include "median_and_worst.hpp"

namespace {
struct BenchReading {
  double depth = 0.0;
  double force = 0.0;
  KDL::Frame pose;
  int samples = 0;
};
}  // namespace

template <>
struct cobra::core::DataTypeTraits<BenchReading> : cobra::core::RecordTraits<BenchReading> {
  static constexpr std::string_view name = "bench.Reading";
  static constexpr auto fields =
      std::tuple{field("depth", &BenchReading::depth, "m"), field("force", &BenchReading::force, "N"),
                 field("pose", &BenchReading::pose), field("samples", &BenchReading::samples, "1")};
};

namespace {

using namespace cobra;

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;

using cobra::bench::maxOf;
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTimePerRepetition);
}

template <class T>
T sample();
template <>
double sample<double>() { return 1.5; }
template <>
KDL::Frame sample<KDL::Frame>() { return KDL::Frame(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(1, 2, 3)); }
template <>
BenchReading sample<BenchReading>() { return {0.05, 2.5, sample<KDL::Frame>(), 7}; }

/// The Lua expression of the sample, in the type's Lua form.
template <class T>
const char* luaSample();
template <>
const char* luaSample<double>() { return "1.5"; }
template <>
const char* luaSample<KDL::Frame>() { return "{p = {x = 1, y = 2, z = 3}, M = {x = 0, y = 0, z = 0, w = 1}}"; }
template <>
const char* luaSample<BenchReading>() {
  return "{depth = 0.05, force = 2.5, pose = {p = {x = 1, y = 2, z = 3}, M = {x = 0, y = 0, z = 0, w = 1}}, samples = 7}";
}

void registerOnce() {
  static const bool done = [] {
    types::registerBuiltins();
    types::registerType<BenchReading>();
    return true;
  }();
  (void)done;
}

template <class T>
struct Ports {
  Ports() {
    out.setDataSample(sample<T>());
    core::connect(out, in, core::ConnPolicy::data());
  }
  core::OutputPort<T> out{"out", "", ""};
  core::InputPort<T> in{"in", "", ""};
};

template <class T>
void Port_Typed(benchmark::State& state) {
  Ports<T> ports;
  T value = sample<T>(), got = value;
  for (auto _ : state) {
    ports.out.write(value);
    benchmark::DoNotOptimize(ports.in.read(got));
  }
}

template <class T>
void Port_Text(benchmark::State& state) {
  Ports<T> ports;
  const std::string text = core::printValue(sample<T>());
  std::string got;
  for (auto _ : state) {
    ports.out.writeText(text);
    benchmark::DoNotOptimize(ports.in.readText(got));
  }
}

template <class T>
void LuaProperty_Codec(benchmark::State& state) {
  registerOnce();
  script::LuaState lua;
  lua.run(std::string("value = ") + luaSample<T>());
  lua_getglobal(lua.get(), "value");
  core::Property<T> property("p", sample<T>(), "", "");
  const script::Conversion* conversion = script::findConversion(core::typeInfo<T>());
  std::any any;
  for (auto _ : state) {
    conversion->read(lua.get(), -1, any);
    conversion->set_property(property, any);
  }
}

template <class T>
void LuaProperty_Text(benchmark::State& state) {
  script::LuaState lua;
  lua.run("value = [=[" + core::printValue(sample<T>()) + "]=]");
  lua_getglobal(lua.get(), "value");
  core::Property<T> property("p", sample<T>(), "", "");
  for (auto _ : state) property.setFromText(lua_tostring(lua.get(), -1));
}

template <class T>
void CsvRow_Codec(benchmark::State& state) {
  registerOnce();
  core::OutputPort<T> out("out", "", "m");
  out.setDataSample(sample<T>());
  const components::CsvType* entry = components::findCsvType(core::typeInfo<T>());
  auto source = entry->make_source(out, out.makeReader("reader", ""), 0);
  core::connectPorts(out, source->reader());
  std::vector<char> buffer(source->maxBytes() + 1);
  const T value = sample<T>();
  for (auto _ : state) {
    out.write(value);
    source->sample();
    components::RowWriter row(buffer.data(), buffer.size());
    source->format(row);
    benchmark::DoNotOptimize(row.size());
  }
}

template <class T>
void CsvRow_Text(benchmark::State& state) {
  core::OutputPort<T> out("out", "", "m");
  core::InputPort<T> in("in", "", "m");
  out.setDataSample(sample<T>());
  core::connect(out, in, core::ConnPolicy::data());
  std::array<char, 512> buffer{};
  const T value = sample<T>();
  T got = value;
  for (auto _ : state) {
    out.write(value);
    in.read(got);
    components::RowWriter row(buffer.data(), buffer.size());
    row.text(core::printValue(got));
    benchmark::DoNotOptimize(row.size());
  }
}

#define COBRA_TYPES_BENCH(Group)                                          \
  BENCHMARK_TEMPLATE(Group, double)->Apply(configure);                    \
  BENCHMARK_TEMPLATE(Group, KDL::Frame)->Apply(configure);                \
  BENCHMARK_TEMPLATE(Group, BenchReading)->Apply(configure)

COBRA_TYPES_BENCH(Port_Typed);
COBRA_TYPES_BENCH(Port_Text);
COBRA_TYPES_BENCH(LuaProperty_Codec);
COBRA_TYPES_BENCH(LuaProperty_Text);
COBRA_TYPES_BENCH(CsvRow_Codec);
COBRA_TYPES_BENCH(CsvRow_Text);

}  // namespace

BENCHMARK_MAIN();
