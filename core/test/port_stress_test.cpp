// Concurrency stress of the data-flow runtime (ARCHITECTURE §4): one writer and several readers
// through real port connections of every policy, property sets applied to a running periodic
// component, and connections made and removed while components run. Meant to be run under
// ThreadSanitizer (label "concurrency"), so every run is bounded by a sample count, not by time,
// and every wait loop yields (the CI machine has 2 cores for 4 threads).
//
// Tearing is detectable because each sample is a 64-element vector whose elements all equal the
// sequence number: a value copied while it was being written would mix two numbers.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "cobra/core/core.hpp"

namespace cobra::core {

// Names the policy in GoogleTest's messages ("where GetParam() = buffer(16)").
void PrintTo(const ConnPolicy& policy, std::ostream* os) { *os << policy.describe(); }

namespace {

using Sample = std::vector<double>;
constexpr std::size_t kElements = 64;
constexpr int kReaders = 3;

/// True when `s` has kElements elements all equal; their common value goes to `value`.
bool uniform(const Sample& s, double& value) {
  if (s.size() != kElements) return false;
  value = s[0];
  for (double x : s)
    if (x != value) return false;
  return true;
}

/// What one reader thread saw; written by that thread only, read after join.
struct ReaderLog {
  std::uint64_t new_data = 0;
  std::uint64_t torn = 0;            // samples whose elements differ (or wrong size)
  std::uint64_t not_increasing = 0;  // NewData whose number is not above the previous one
  std::uint64_t gaps = 0;            // NewData that is not previous + 1 (must be 0 for buffer + retry)
  std::uint64_t old_mismatch = 0;    // OldData that is not the last NewData again
  double last = 0.0;
};

/// Reads `in` until the writer is done and everything it left was read. `done` is loaded before
/// each read, so a read that follows a true `done` sees every sample the writer pushed.
void readUntilDrained(InputPort<Sample>& in, const std::atomic<bool>& done, ReaderLog& log) {
  Sample value(kElements, -1.0);
  for (;;) {
    const bool writer_done = done.load(std::memory_order_acquire);
    const FlowStatus status = in.read(value);
    double v = 0.0;
    if (status == FlowStatus::NewData) {
      ++log.new_data;
      if (!uniform(value, v)) {
        ++log.torn;
        continue;
      }
      if (v <= log.last) ++log.not_increasing;
      if (v != log.last + 1.0) ++log.gaps;
      log.last = v;
      continue;
    }
    if (status == FlowStatus::OldData && (!uniform(value, v) || v != log.last)) ++log.old_mismatch;
    if (writer_done) return;
    std::this_thread::yield();
  }
}

void expectClean(const ReaderLog& log, int reader) {
  EXPECT_EQ(log.torn, 0u) << "reader " << reader << " saw torn samples";
  EXPECT_EQ(log.not_increasing, 0u) << "reader " << reader << " saw a sequence number go back or repeat";
  EXPECT_EQ(log.old_mismatch, 0u) << "reader " << reader << " got OldData that is not the last value";
  EXPECT_GT(log.new_data, 0u) << "reader " << reader;
}

class PortStress : public ::testing::TestWithParam<ConnPolicy> {};

// One output port fanned out to kReaders inputs, each read on its own thread. The writer never
// retries: data and circular connections overwrite, buffer connections drop when full. Every
// reader must see strictly increasing, untorn samples; with data and circular it must end on the
// last value written (the newest sample is never lost).
TEST_P(PortStress, OneWriterManyReadersSeeUntornIncreasingSamples) {
  const ConnPolicy policy = GetParam();
  constexpr std::uint64_t kWrites = 200'000;
  OutputPort<Sample> out{"out", "", "1", Sample(kElements, 0.0)};
  std::vector<std::unique_ptr<InputPort<Sample>>> ins;
  for (int r = 0; r < kReaders; ++r) {
    ins.push_back(std::make_unique<InputPort<Sample>>("in" + std::to_string(r), "", "1"));
    connect(out, *ins.back(), policy);
  }

  std::atomic<bool> done{false};
  std::vector<ReaderLog> logs(kReaders);
  std::vector<std::thread> readers;
  for (int r = 0; r < kReaders; ++r) readers.emplace_back([&, r] { readUntilDrained(*ins[r], done, logs[r]); });

  Sample value(kElements, 0.0);
  std::uint64_t dropped = 0;
  for (std::uint64_t seq = 1; seq <= kWrites; ++seq) {
    value.assign(kElements, static_cast<double>(seq));  // same size: no allocation
    if (out.write(value) == WriteStatus::Dropped) ++dropped;
    if (seq % 64 == 0) std::this_thread::yield();  // lets readers run on a 2-core machine
  }
  done.store(true, std::memory_order_release);
  for (auto& t : readers) t.join();

  for (int r = 0; r < kReaders; ++r) {
    expectClean(logs[r], r);
    if (policy.kind != ConnPolicy::Kind::Buffer) {
      EXPECT_EQ(logs[r].last, static_cast<double>(kWrites)) << "reader " << r << " missed the last value";
    } else {
      EXPECT_LE(logs[r].new_data, kWrites) << "reader " << r;
    }
  }
  if (policy.kind != ConnPolicy::Kind::Buffer) {
    EXPECT_EQ(dropped, 0u);
  }
}

std::string policyTestName(const ::testing::TestParamInfo<ConnPolicy>& param_info) {
  switch (param_info.param.kind) {
    case ConnPolicy::Kind::Data: return "Data";
    case ConnPolicy::Kind::Buffer: return "Buffer16";
    case ConnPolicy::Kind::Circular: return "Circular16";
  }
  return "Unknown";
}

INSTANTIATE_TEST_SUITE_P(Policies, PortStress,
                         ::testing::Values(ConnPolicy::data(), ConnPolicy::buffer(16), ConnPolicy::circular(16)),
                         policyTestName);

// buffer(16) is a lossless FIFO when the writer retries the writes it reports Dropped: each
// reader must receive every number exactly once, in order. One output port per reader, because
// a write to a fanned-out port that drops on one connection succeeds on the others, so retrying
// it would duplicate samples there.
TEST(PortStressBuffer, RetriedWritesReachAReaderThatKeepsUpExactlyOnceInOrder) {
  constexpr std::uint64_t kWrites = 100'000;
  std::vector<std::unique_ptr<OutputPort<Sample>>> outs;
  std::vector<std::unique_ptr<InputPort<Sample>>> ins;
  for (int r = 0; r < kReaders; ++r) {
    outs.push_back(std::make_unique<OutputPort<Sample>>("out" + std::to_string(r), "", "1", Sample(kElements, 0.0)));
    ins.push_back(std::make_unique<InputPort<Sample>>("in" + std::to_string(r), "", "1"));
    connect(*outs.back(), *ins.back(), ConnPolicy::buffer(16));
  }

  std::atomic<bool> done{false};
  std::vector<ReaderLog> logs(kReaders);
  std::vector<std::thread> readers;
  for (int r = 0; r < kReaders; ++r) readers.emplace_back([&, r] { readUntilDrained(*ins[r], done, logs[r]); });

  Sample value(kElements, 0.0);
  std::uint64_t retries = 0;
  for (std::uint64_t seq = 1; seq <= kWrites; ++seq) {
    value.assign(kElements, static_cast<double>(seq));
    for (auto& out : outs) {
      while (out->write(value) == WriteStatus::Dropped) {
        ++retries;
        std::this_thread::yield();
      }
    }
  }
  done.store(true, std::memory_order_release);
  for (auto& t : readers) t.join();

  for (int r = 0; r < kReaders; ++r) {
    expectClean(logs[r], r);
    EXPECT_EQ(logs[r].gaps, 0u) << "reader " << r << " missed or repeated a sample";
    EXPECT_EQ(logs[r].new_data, kWrites) << "reader " << r;
    EXPECT_EQ(logs[r].last, static_cast<double>(kWrites)) << "reader " << r;
  }
  RecordProperty("retries", std::to_string(retries));
}

// Several writer threads into one input (a supervisor's event port): the reader skips its scan
// while the buffered write count has not changed since a scan found every connection empty, so a
// sample pushed during a scan must still be read by a later call. Each writer's samples arrive
// exactly once and in order.
TEST(PortStressFanIn, EveryWritersSamplesReachAReaderThatSkipsEmptyScans) {
  constexpr int kWriters = 3;
  constexpr std::uint64_t kWrites = 20'000;
  constexpr double kWriterStride = 1e6;  // writer w's samples are w * 1e6 + seq (exact doubles)
  InputPort<double> in{"in", "", "1"};
  std::vector<std::unique_ptr<OutputPort<double>>> outs;
  for (int w = 0; w < kWriters; ++w) {
    outs.push_back(std::make_unique<OutputPort<double>>("out" + std::to_string(w), "", "1"));
    connect(*outs.back(), in, ConnPolicy::buffer(8));
  }
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w) {
    writers.emplace_back([&, w] {
      for (std::uint64_t seq = 1; seq <= kWrites; ++seq) {
        while (outs[w]->write(w * kWriterStride + static_cast<double>(seq)) == WriteStatus::Dropped)
          std::this_thread::yield();
      }
    });
  }
  std::vector<std::uint64_t> last(kWriters, 0);
  std::uint64_t received = 0, out_of_order = 0, empty_reads = 0;
  while (received < kWriters * kWrites) {
    double v = 0.0;
    if (in.readNew(v) != FlowStatus::NewData) {
      ++empty_reads;
      std::this_thread::yield();
      continue;
    }
    const auto w = static_cast<std::size_t>(v / kWriterStride);
    const auto seq = static_cast<std::uint64_t>(v - static_cast<double>(w) * kWriterStride);
    ASSERT_LT(w, static_cast<std::size_t>(kWriters));
    if (seq != last[w] + 1) ++out_of_order;
    last[w] = seq;
    ++received;
  }
  for (auto& t : writers) t.join();
  double v = 0.0;
  EXPECT_EQ(in.readNew(v), FlowStatus::OldData) << "a sample beyond the writes";
  EXPECT_EQ(out_of_order, 0u);
  for (int w = 0; w < kWriters; ++w) EXPECT_EQ(last[w], kWrites) << "writer " << w;
  RecordProperty("empty_reads", std::to_string(empty_reads));
}

// ---------------------------------------------------------------------------------------------
// Properties set from another thread while a periodic component reads them in updateHook. The
// setter sets `a` to k (a 64-element vector) and then `b` to k; each set is applied between two
// steps, so every step must see untorn values with a == b or a == b + 1, never decreasing.

class PropertyWatcher final : public Component {
 public:
  PropertyWatcher() : Component("watcher", Role::Calculation, "reads two properties every step") {
    addProperty(a_);
    addProperty(b_);
  }
  std::uint64_t steps = 0;
  std::uint64_t torn = 0;
  std::uint64_t inconsistent = 0;  // a - b outside {0, 1}
  std::uint64_t decreasing = 0;
  std::uint64_t changes_seen = 0;

 protected:
  void updateHook() override {
    ++steps;
    double a = 0.0;
    if (!uniform(a_.get(), a)) {
      ++torn;
      return;
    }
    const double b = b_.get();
    if (!(a - b == 0.0 || a - b == 1.0)) ++inconsistent;
    if (a < last_a_ || b < last_b_) ++decreasing;
    if (a != last_a_) ++changes_seen;
    last_a_ = a;
    last_b_ = b;
  }

 private:
  Property<Sample> a_{"a", Sample(kElements, 0.0), "1", "64 equal numbers"};
  Property<double> b_{"b", 0.0, "1", "follows a"};
  double last_a_ = 0.0;
  double last_b_ = 0.0;
};

TEST(PropertyStress, SetsFromAnotherThreadApplyBetweenStepsOfAPeriodicComponent) {
  constexpr int kSets = 600;
  PropertyWatcher watcher;
  watcher.setActivity(std::make_unique<PeriodicActivity>(std::chrono::microseconds(200), 50, Scheduler::Other));
  ASSERT_TRUE(watcher.configure());
  ASSERT_TRUE(watcher.start());

  std::atomic<bool> setter_done{false};
  std::uint64_t wrong_read_back = 0;
  std::thread setter([&] {
    Sample a(kElements, 0.0);
    for (int k = 1; k <= kSets; ++k) {
      a.assign(kElements, k);
      watcher.setProperty("a", a);
      watcher.setProperty("b", static_cast<double>(k));
      if (watcher.getProperty<double>("b") != k) ++wrong_read_back;
    }
    setter_done.store(true, std::memory_order_release);
  });
  // A second outside reader: value() and valueText() take the lock the activity thread applies
  // changes under, so they never see a half-applied value.
  std::uint64_t outside_torn = 0;
  while (!setter_done.load(std::memory_order_acquire)) {
    double a = 0.0;
    if (!uniform(watcher.getProperty<Sample>("a"), a)) ++outside_torn;
    (void)watcher.property("b").valueText();
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  setter.join();
  ASSERT_TRUE(watcher.stop());

  EXPECT_EQ(wrong_read_back, 0u);
  EXPECT_EQ(outside_torn, 0u);
  EXPECT_EQ(watcher.torn, 0u);
  EXPECT_EQ(watcher.inconsistent, 0u);
  EXPECT_EQ(watcher.decreasing, 0u);
  EXPECT_GT(watcher.steps, 0u);
  EXPECT_GT(watcher.changes_seen, 1u);
  EXPECT_EQ(watcher.getProperty<Sample>("a"), Sample(kElements, kSets));
  EXPECT_EQ(watcher.getProperty<double>("b"), kSets);
}

// The same, while the deployer thread starts and stops the component over and over: a set()
// that arrives while no activity thread runs is applied at once, and must then still never
// overlap a hook (startHook and stopHook read the property too) nor the first step of a thread
// that is just starting.

class LifecycleWatcher final : public Component {
 public:
  LifecycleWatcher() : Component("lifecycle", Role::Calculation, "reads a property in every hook") {
    addProperty(a_);
  }
  std::atomic<std::uint64_t> torn{0};
  std::atomic<std::uint64_t> decreasing{0};
  std::atomic<std::uint64_t> updates{0};

 protected:
  bool startHook() override {
    check();
    return true;
  }
  void updateHook() override {
    check();
    updates.fetch_add(1, std::memory_order_relaxed);
  }
  void stopHook() override { check(); }

 private:
  void check() {
    double a = 0.0;
    if (!uniform(a_.get(), a)) {
      torn.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    if (a < last_a_) decreasing.fetch_add(1, std::memory_order_relaxed);
    last_a_ = a;
  }
  Property<Sample> a_{"a", Sample(kElements, 0.0), "1", "64 equal numbers"};
  double last_a_ = 0.0;  // hooks never overlap, whichever thread runs them
};

TEST(PropertyStress, SetsFromAnotherThreadWhileTheComponentStartsAndStops) {
  constexpr int kCycles = 200;
  LifecycleWatcher watcher;
  watcher.setActivity(std::make_unique<PeriodicActivity>(std::chrono::microseconds(200), 50, Scheduler::Other));
  ASSERT_TRUE(watcher.configure());

  std::atomic<bool> stop_setting{false};
  int sets = 0;
  std::thread setter([&] {
    Sample a(kElements, 0.0);
    while (!stop_setting.load(std::memory_order_acquire)) {
      ++sets;
      a.assign(kElements, sets);
      watcher.setProperty("a", a);
      std::this_thread::yield();
    }
  });
  for (int cycle = 0; cycle < kCycles; ++cycle) {
    ASSERT_TRUE(watcher.start());
    std::this_thread::sleep_for(std::chrono::microseconds(300));
    ASSERT_TRUE(watcher.stop());
  }
  stop_setting.store(true, std::memory_order_release);
  setter.join();

  EXPECT_EQ(watcher.torn.load(), 0u);
  EXPECT_EQ(watcher.decreasing.load(), 0u);
  EXPECT_GT(watcher.updates.load(), 0u);
  EXPECT_EQ(watcher.getProperty<Sample>("a"), Sample(kElements, sets));
}

// ---------------------------------------------------------------------------------------------
// Connections made and removed from the main thread while a periodic writer writes and a
// periodic reader reads: the ports' channel lists change only between steps of their owners.

class SeqWriter final : public Component {
 public:
  SeqWriter() : Component("writer", Role::Calculation, "writes 64 copies of a step counter") {
    out.setDataSample(Sample(kElements, 0.0));
    addPort(out);
  }
  OutputPort<Sample> out{"out", "step counter, 64 times", "1"};

 protected:
  void updateHook() override {
    ++seq_;
    value_.assign(kElements, static_cast<double>(seq_));
    out.write(value_);
  }

 private:
  std::uint64_t seq_ = 0;
  Sample value_ = Sample(kElements, 0.0);
};

class SeqReader final : public Component {
 public:
  SeqReader() : Component("reader", Role::Calculation, "checks the writer's counter") { addPort(in); }
  InputPort<Sample> in{"in", "step counter, 64 times", "1"};
  ReaderLog log;

 protected:
  void updateHook() override {
    double v = 0.0;
    if (in.read(value_) != FlowStatus::NewData) return;
    ++log.new_data;
    if (!uniform(value_, v)) {
      ++log.torn;
      return;
    }
    if (v <= log.last) ++log.not_increasing;
    log.last = v;
  }

 private:
  Sample value_ = Sample(kElements, 0.0);
};

TEST(ConnectionStress, ConnectAndDisconnectWhilePeriodicComponentsWriteAndRead) {
  constexpr int kCycles = 150;
  const ConnPolicy policies[] = {ConnPolicy::data(), ConnPolicy::buffer(16), ConnPolicy::circular(16)};
  SeqWriter writer;
  SeqReader reader;
  for (Component* c : {static_cast<Component*>(&writer), static_cast<Component*>(&reader)}) {
    c->setActivity(std::make_unique<PeriodicActivity>(std::chrono::microseconds(200), 50, Scheduler::Other));
    ASSERT_TRUE(c->configure());
    ASSERT_TRUE(c->start());
  }
  // A port of no component, read by this thread: its side of a connection changes at once.
  InputPort<Sample> probe{"probe", "", "1"};
  ReaderLog probe_log;
  Sample value(kElements, 0.0);
  int probe_timeouts = 0;

  for (int cycle = 0; cycle < kCycles; ++cycle) {
    const ConnPolicy policy = policies[cycle % 3];
    connect(writer.out, reader.in, policy);
    connect(writer.out, probe, policy);
    EXPECT_TRUE(writer.out.connectedTo(reader.in));
    // Wait (bounded) for one sample through the new connection.
    bool got = false;
    for (int i = 0; i < 20'000 && !got; ++i) {
      if (probe.read(value) == FlowStatus::NewData) {
        got = true;
        double v = 0.0;
        ++probe_log.new_data;
        if (!uniform(value, v)) ++probe_log.torn;
        else if (v <= probe_log.last) ++probe_log.not_increasing;
        else probe_log.last = v;
      } else {
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
    }
    if (!got) ++probe_timeouts;
    // Alternate the two ways of removing a connection.
    if (cycle % 2 == 0) {
      EXPECT_TRUE(disconnectPorts(writer.out, reader.in));
      EXPECT_TRUE(disconnectPorts(writer.out, probe));
    } else {
      reader.in.disconnect();
      probe.disconnect();
    }
    EXPECT_FALSE(writer.out.connectedTo(reader.in));
  }
  ASSERT_TRUE(writer.stop());
  ASSERT_TRUE(reader.stop());

  EXPECT_EQ(probe_timeouts, 0);
  EXPECT_EQ(probe_log.torn, 0u);
  EXPECT_EQ(probe_log.not_increasing, 0u);
  EXPECT_EQ(reader.log.torn, 0u);
  EXPECT_EQ(reader.log.not_increasing, 0u);
  EXPECT_GT(reader.log.new_data, 0u);
  EXPECT_FALSE(writer.out.connected());
  EXPECT_TRUE(writer.out.connections().empty());
}

}  // namespace
}  // namespace cobra::core
