// The per-type paths a control loop and its recording take, written only against APIs that did
// not change when types became open (one registration per type, ARCHITECTURE §2): so the same
// file builds at an older revision, and bench/compare_revisions.sh runs both builds side by side
// in one run ("before" and "after"). For double, KDL.Frame and KDL.JntArray (6 joints):
//  - PortWriteRead: one write then one read on one thread, through a `data` connection (the
//    triple buffer) and a `buffer(8)` connection (the slot queue and free list).
//  - LuaPropertySet: a Lua value read by the type's Lua conversion (script::findConversion) and
//    set on a Property, as a deployment file's property assignment does.
//  - CsvRecord: one step of a Reporter recording one port of the type (on the lockstep clock,
//    file /dev/null): the sample read, formatted into its CSV columns and queued for the writer
//    thread. The queue holds every row of a repetition (a fixed count), so none is dropped (a
//    dropped row would skip the copy): the counter rows_dropped says so.
// Every benchmark runs 10 repetitions and reports their median and worst case ("max").

#include <benchmark/benchmark.h>

#include <algorithm>
#include <any>
#include <chrono>
#include <string>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <lua.hpp>

#include "cobra/components/reporting/reporter.hpp"
#include "cobra/core/core.hpp"
#include "cobra/script/convert.hpp"
#include "cobra/script/lua_state.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace cobra;
using namespace std::chrono_literals;

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;
constexpr unsigned kJoints = 6;
/// Steps per repetition of CsvRecord, and its queue's rows (all of them fit: nothing dropped).
constexpr int kRecordSteps = 100'000;
constexpr int kRecordQueueRows = 131'072;

using cobra::bench::maxOf;
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTimePerRepetition);
}

void configureRecord(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->Iterations(kRecordSteps);
}

template <class T>
T sample();
template <>
double sample<double>() { return 1.5; }
template <>
KDL::Frame sample<KDL::Frame>() { return KDL::Frame(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(1, 2, 3)); }
template <>
KDL::JntArray sample<KDL::JntArray>() {
  KDL::JntArray q(kJoints);
  for (unsigned i = 0; i < kJoints; ++i) q(i) = 0.1 * (i + 1);
  return q;
}

/// The sample's Lua form (the forms cobra's Lua conversions accept at both revisions).
template <class T>
const char* luaSample();
template <>
const char* luaSample<double>() { return "1.5"; }
template <>
const char* luaSample<KDL::Frame>() { return "{p = {x = 1, y = 2, z = 3}, M = {x = 0, y = 0, z = 0, w = 1}}"; }
template <>
const char* luaSample<KDL::JntArray>() { return "{0.1, 0.2, 0.3, 0.4, 0.5, 0.6}"; }

template <class T>
std::size_t elementsOf() {
  return std::is_same_v<T, KDL::JntArray> ? kJoints : 0;
}

enum class Policy { Data, Buffer };

template <class T, Policy P>
void PortWriteRead(benchmark::State& state) {
  core::OutputPort<T> out("out", "", "");
  core::InputPort<T> in("in", "", "");
  out.setDataSample(sample<T>());
  core::connect(out, in, P == Policy::Data ? core::ConnPolicy::data() : core::ConnPolicy::buffer(8));
  const T value = sample<T>();
  T got = value;
  for (auto _ : state) {
    out.write(value);
    benchmark::DoNotOptimize(in.read(got));
  }
}

template <class T>
void LuaPropertySet(benchmark::State& state) {
  script::LuaState lua;
  lua.run(std::string("value = ") + luaSample<T>());
  lua_getglobal(lua.get(), "value");
  core::Property<T> property("p", sample<T>(), "", "");
  const script::Conversion* conversion = script::findConversion(core::typeInfo<T>());
  if (conversion == nullptr) {
    state.SkipWithError("no Lua conversion for the type");
    return;
  }
  std::any any;
  for (auto _ : state) {
    conversion->read(lua.get(), -1, any);
    conversion->set_property(property, any);
  }
}

/// A component with one output port of T, which the Reporter records.
template <class T>
class Source final : public core::Component {
 public:
  Source() : core::Component("Src", core::Role::Calculation, "writes the recorded value") {
    out_.setDataSample(sample<T>());
    addPort(out_);
  }
  core::OutputPort<T> out_{"out", "the recorded value", "1"};
};

template <class T>
void CsvRecord(benchmark::State& state) {
  core::LockstepClock clock;
  Source<T> source;
  components::Reporter reporter("Rep");
  reporter.reportPort(source.port("out"), elementsOf<T>());
  reporter.setProperty("file_path", std::string("/dev/null"));
  reporter.setProperty("queue_rows", kRecordQueueRows);
  clock.add(reporter, 1ms);
  if (!reporter.configure() || !reporter.start()) {
    state.SkipWithError("the Reporter did not start");
    return;
  }
  const T value = sample<T>();
  for (auto _ : state) {
    source.out_.write(value);
    clock.advance(1ms);
  }
  state.counters["rows_dropped"] = reporter.template getProperty<int>("rows_dropped");
  (void)reporter.stop();
}

#define COBRA_TYPE_PATHS(Group)                            \
  BENCHMARK_TEMPLATE(Group, double)->Apply(configure);     \
  BENCHMARK_TEMPLATE(Group, KDL::Frame)->Apply(configure); \
  BENCHMARK_TEMPLATE(Group, KDL::JntArray)->Apply(configure)

BENCHMARK_TEMPLATE(PortWriteRead, double, Policy::Data)->Name("PortWriteRead/data/double")->Apply(configure);
BENCHMARK_TEMPLATE(PortWriteRead, KDL::Frame, Policy::Data)->Name("PortWriteRead/data/Frame")->Apply(configure);
BENCHMARK_TEMPLATE(PortWriteRead, KDL::JntArray, Policy::Data)->Name("PortWriteRead/data/JntArray")->Apply(configure);
BENCHMARK_TEMPLATE(PortWriteRead, double, Policy::Buffer)->Name("PortWriteRead/buffer/double")->Apply(configure);
BENCHMARK_TEMPLATE(PortWriteRead, KDL::Frame, Policy::Buffer)->Name("PortWriteRead/buffer/Frame")->Apply(configure);
BENCHMARK_TEMPLATE(PortWriteRead, KDL::JntArray, Policy::Buffer)
    ->Name("PortWriteRead/buffer/JntArray")
    ->Apply(configure);
COBRA_TYPE_PATHS(LuaPropertySet);
BENCHMARK_TEMPLATE(CsvRecord, double)->Apply(configureRecord);
BENCHMARK_TEMPLATE(CsvRecord, KDL::Frame)->Apply(configureRecord);
BENCHMARK_TEMPLATE(CsvRecord, KDL::JntArray)->Apply(configureRecord);

}  // namespace

BENCHMARK_MAIN();
