// Proves the real-time contract of ARCHITECTURE §4: in steady state, port write + read and the
// update step of a Running component perform zero heap allocations. A counting global
// operator new replaces the library one for this test executable only.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"


namespace cobra::core {
namespace {

using cobra::test_support::allocationsDuring;

TEST(RealtimeAlloc, CounterSeesAllocations) {
  // Guards against a counter that cannot fail.
  static std::vector<double>* volatile escaped = nullptr;  // keeps the compiler from eliding new
  const long n = allocationsDuring([] {
    escaped = new std::vector<double>(100);
    delete escaped;
  });
  EXPECT_GE(n, 2);
}

TEST(RealtimeAlloc, PortWriteReadAllocatesNothingForEveryPolicyAndBuiltinType) {
  OutputPort<double> out_d{"d_out", "", "1"};
  InputPort<double> in_data{"in_data", "", "1"}, in_buffer{"in_buffer", "", "1"}, in_circular{"in_circular", "", "1"};
  connect(out_d, in_data, ConnPolicy::data());
  connect(out_d, in_buffer, ConnPolicy::buffer(4));
  connect(out_d, in_circular, ConnPolicy::circular(4));

  const std::vector<double> six(6, 0.5);
  OutputPort<std::vector<double>> out_v{"v_out", "", "1", six};
  InputPort<std::vector<double>> in_v{"v_in", "", "1"};
  connect(out_v, in_v, ConnPolicy::circular(3));
  std::vector<double> v_read = six;

  OutputPort<KDL::Frame> out_f{"f_out", "", "m"};
  InputPort<KDL::Frame> in_f{"f_in", "", "m"};
  connect(out_f, in_f);
  KDL::JntArray joints(7);
  OutputPort<KDL::JntArray> out_j{"j_out", "", "rad", joints};
  InputPort<KDL::JntArray> in_j{"j_in", "", "rad"};
  connect(out_j, in_j, ConnPolicy::buffer(2));
  KDL::JntArray j_read(7);

  OutputPort<Event> out_e{"e_out", "", ""};
  InputPort<Event> in_e{"e_in", "", ""};
  connect(out_e, in_e, ConnPolicy::buffer(8));

  double d = 0.0;
  KDL::Frame f;
  Event e;
  auto cycle = [&](int i) {
    out_d.write(i);
    in_data.read(d);
    in_buffer.read(d);
    in_circular.read(d);
    out_v.write(six);
    in_v.read(v_read);
    out_f.write(KDL::Frame(KDL::Vector(i, 0, 0)));
    in_f.read(f);
    out_j.write(joints);
    in_j.read(j_read);
    out_e.write(Event{"e_tick", "test", std::chrono::nanoseconds(i)});
    in_e.read(e);
  };
  for (int i = 0; i < 10; ++i) cycle(i);  // warm-up: nothing should be needed, but be fair
  const long n = allocationsDuring([&] {
    for (int i = 0; i < 10000; ++i) cycle(i);
  });
  EXPECT_EQ(n, 0);
  EXPECT_EQ(d, 9999.0);
  EXPECT_EQ(e.name, "e_tick");
}

/// A component doing typical real-time work: reads a Frame and a vector, reads properties,
/// writes results and emits an event now and then.
class Worker : public Component {
 public:
  explicit Worker(std::string name) : Component(std::move(name), Role::Calculation, "alloc test worker") {
    addEventPort(in_);
    addPort(out_);
    addProperty(gain_);
  }
  int updates = 0;

 protected:
  void updateHook() override {
    double u = 0.0;
    while (in_.read(u) == FlowStatus::NewData) out_.write(gain_() * u);
    if (++updates % 100 == 0) emitEvent("e_hundred_updates");
  }

 private:
  InputPort<double> in_{"in", "input", "1"};
  OutputPort<double> out_{"out", "output", "1"};
  Property<double> gain_{"gain", 2.0, "1", "gain"};
};

TEST(RealtimeAlloc, UpdateOfRunningComponentsOnLockstepClockAllocatesNothing) {
  Worker first("First"), second("Second");
  OutputPort<double> source{"source", "", "1"};
  InputPort<double> sink{"sink", "", "1"};
  InputPort<Event> events{"events_in", "", ""};
  connect(source, static_cast<InputPort<double>&>(first.port("in")));
  connectPorts(first.port("out"), second.port("in"), ConnPolicy::buffer(4));
  connectPorts(second.port("out"), sink);
  connectPorts(first.port("events"), events, ConnPolicy::circular(4));

  LockstepClock clock;
  clock.add(first, std::chrono::milliseconds(1));
  clock.add(second, std::chrono::nanoseconds(0));
  ASSERT_TRUE(first.configure());
  ASSERT_TRUE(second.configure());
  ASSERT_TRUE(first.start());
  ASSERT_TRUE(second.start());

  double y = 0.0;
  Event e;
  source.write(1.0);
  clock.advance(std::chrono::milliseconds(10));  // warm-up
  const long n = allocationsDuring([&] {
    for (int i = 0; i < 5000; ++i) {
      source.write(i);
      clock.advance(std::chrono::milliseconds(1));
      sink.read(y);
      events.read(e);
    }
  });
  EXPECT_EQ(n, 0);
  EXPECT_EQ(y, 4.0 * 4999);
  EXPECT_EQ(e.name, "e_hundred_updates");
  EXPECT_EQ(first.state(), State::Running);
}

TEST(RealtimeAlloc, SlaveActivityStepAllocatesNothing) {
  Worker worker("Worker");
  OutputPort<double> source{"source", "", "1"};
  connect(source, static_cast<InputPort<double>&>(worker.port("in")));
  ASSERT_TRUE(worker.configure());
  ASSERT_TRUE(worker.start());
  auto& slave = static_cast<SlaveActivity&>(worker.activity());
  const long n = allocationsDuring([&] {
    for (int i = 0; i < 1000; ++i) {
      source.write(i);
      slave.step();
    }
  });
  EXPECT_EQ(n, 0);
  EXPECT_EQ(worker.updates, 1000);
}

}  // namespace
}  // namespace cobra::core
