// The real-time side of a dds connection allocates nothing (ARCHITECTURE §4): OutputPort::write
// into a writer's end and InputPort::read from a reader's end, while the transport's threads and
// Fast DDS's own (which do allocate) carry the samples between two participants. Counted per
// thread: only the allocations of the thread that writes or reads the port. For cobra's built-in
// types and for a record.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "cobra/core/port.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "cobra/dds/register_type.hpp"
#include "dds_test_support.hpp"
#include "test_records.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;
using test_support::allocationsOnThisThreadDuring;

TEST(DdsAllocations, WritingAFrameIntoTheWritersEndAllocatesNothing) {
  test::RegisteredTransport a("dds_alloc_wa", 121, "cobra_a");
  test::RegisteredTransport b("dds_alloc_wb", 121, "cobra_b");
  core::OutputPort<KDL::Frame> out("pose", "", "m");
  core::InputPort<KDL::Frame> in("pose", "", "m");
  core::connectToTransport(out, a.policy("alloc/pose"));
  core::connectToTransport(in, b.policy("alloc/pose"));
  ASSERT_TRUE(a.transport->waitForMatch("alloc/pose", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("alloc/pose", 5s));

  long allocations = 0;
  KDL::Frame frame;
  for (int i = 0; i < 500; ++i) {
    frame.p.x(0.001 * i);
    allocations += allocationsOnThisThreadDuring([&] { out.write(frame); });
    std::this_thread::sleep_for(100us);
  }
  EXPECT_EQ(allocations, 0);
  KDL::Frame got;  // the samples did travel while being counted
  ASSERT_TRUE(test::pollUntil([&] {
    in.read(got);
    return std::abs(got.p.x() - 0.499) < 1e-12;
  }));
}

TEST(DdsAllocations, WritingAndReadingARecordAllocateNothing) {
  // A record travels by its own type support (record_wire.hpp); the component's side is a
  // channel as for any type. Gains: a double, an int and a bool.
  registerDdsType<test::Gains>();
  test::RegisteredTransport a("dds_alloc_reca", 208, "cobra_a");
  test::RegisteredTransport b("dds_alloc_recb", 208, "cobra_b");
  core::OutputPort<test::Gains> out("gains", "", "");
  core::InputPort<test::Gains> in("gains", "", "");
  core::connectToTransport(out, a.policy("alloc/gains"));
  core::connectToTransport(in, b.policy("alloc/gains"));
  ASSERT_TRUE(a.transport->waitForMatch("alloc/gains", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("alloc/gains", 5s));

  long allocations = 0;
  test::Gains gains{100.0, 0, true};
  test::Gains got;
  for (int i = 1; i <= 300; ++i) {
    gains.samples = i;
    allocations += allocationsOnThisThreadDuring([&] {
      out.write(gains);
      in.read(got);
    });
    std::this_thread::sleep_for(100us);
  }
  EXPECT_EQ(allocations, 0);
  ASSERT_TRUE(test::pollUntil([&] {  // the samples did travel while being counted
    in.read(got);
    return got.samples == 300;
  }));
  EXPECT_EQ(got.stiffness, 100.0);
  EXPECT_TRUE(got.enabled);
}

TEST(DdsAllocations, WritingEventsIntoABufferedWritersEndAllocatesNothing) {
  test::RegisteredTransport a("dds_alloc_ea", 122, "cobra_a");
  test::RegisteredTransport b("dds_alloc_eb", 122, "cobra_b");
  core::OutputPort<core::Event> out("events", "", "");
  core::InputPort<core::Event> in("events", "", "");
  // Room for every event: the end's thread polls (every 0.1 ms) and, with other DDS tests
  // running beside this one on a 2-core machine, was seen starved for 15 ms (150 events).
  core::ConnPolicy policy = core::ConnPolicy::buffer(512);
  policy.options = {{"reliability", "reliable"}, {"depth", "512"}};
  core::connectToTransport(out, a.policy("alloc/events", policy));
  core::connectToTransport(in, b.policy("alloc/events", policy));
  ASSERT_TRUE(a.transport->waitForMatch("alloc/events", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("alloc/events", 5s));

  long allocations = 0;
  int received = 0;
  const auto drain = [&] {  // the reader keeps up, as its component would: a buffer drops when full
    core::Event e;
    while (in.read(e) == core::FlowStatus::NewData) ++received;
    return received == 300;
  };
  core::Event event;
  event.name = "e_tick";
  for (int i = 0; i < 300; ++i) {
    event.stamp = std::chrono::nanoseconds(i);
    allocations += allocationsOnThisThreadDuring([&] { out.write(event); });
    std::this_thread::sleep_for(100us);
    drain();
  }
  EXPECT_EQ(allocations, 0);
  ASSERT_TRUE(test::pollUntil(drain)) << received << " of 300 events arrived";
}

TEST(DdsAllocations, ReadingFromTheReadersEndAllocatesNothing) {
  test::RegisteredTransport a("dds_alloc_ra", 123, "cobra_a");
  test::RegisteredTransport b("dds_alloc_rb", 123, "cobra_b");
  core::OutputPort<std::vector<double>> out("q", "", "rad", std::vector<double>(6, 0.0));
  core::InputPort<std::vector<double>> in("q", "", "rad");
  core::connectToTransport(out, a.policy("alloc/q"));
  core::connectToTransport(in, b.policy("alloc/q"));
  ASSERT_TRUE(a.transport->waitForMatch("alloc/q", 5s));
  ASSERT_TRUE(b.transport->waitForMatch("alloc/q", 5s));

  std::atomic<bool> stop{false};
  std::thread writer([&] {
    std::vector<double> q(6, 0.0);
    while (!stop.load()) {
      q[0] += 1.0;
      out.write(q);
      std::this_thread::sleep_for(200us);
    }
  });
  std::vector<double> got(6, 0.0);  // sized once, as a component's configureHook would
  ASSERT_TRUE(test::pollUntil([&] { return in.read(got) == core::FlowStatus::NewData; }));
  long allocations = 0;
  int fresh = 0;
  const auto until = std::chrono::steady_clock::now() + 1s;
  while (std::chrono::steady_clock::now() < until) {
    allocations += allocationsOnThisThreadDuring([&] {
      if (in.read(got) == core::FlowStatus::NewData) ++fresh;
    });
    std::this_thread::sleep_for(100us);
  }
  stop.store(true);
  writer.join();
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(fresh, 50);  // samples did arrive while reads were counted
  EXPECT_EQ(got.size(), 6U);
}

}  // namespace
}  // namespace cobra::dds
