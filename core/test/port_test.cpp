// Unit tests of ports (port.hpp): connecting typed and by name, refusals and their messages,
// fan-out and fan-in, disconnection, write/read statuses and event ports.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <kdl/frames.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::messageOf;
using cobra::test_support::waitUntil;

using namespace std::chrono_literals;

class Source : public Component {
 public:
  explicit Source(std::string name) : Component(std::move(name), Role::Calculation, "writes values") { addPort(out); }
  OutputPort<double> out{"out", "value", "m"};
};

class IntSink : public Component {
 public:
  explicit IntSink(std::string name) : Component(std::move(name), Role::Calculation, "reads ints") { addPort(in); }
  InputPort<int> in{"in", "count", "1"};
};

/// Reads `in` (an event port) on every update and keeps the last value.
class Sink : public Component {
 public:
  explicit Sink(std::string name) : Component(std::move(name), Role::Calculation, "reads values") {
    addEventPort(in);
    addPort(plain);
  }
  InputPort<double> in{"in", "value", "m"};
  InputPort<double> plain{"plain", "not an event port", "m"};
  std::atomic<double> last{0.0};

 protected:
  void updateHook() override {
    double v = 0.0;
    if (in.read(v) == FlowStatus::NewData) last.store(v);
  }
};

// --- connecting -------------------------------------------------------------------------------

TEST(Port, FullNameIsOwnerDotPortOrJustThePortName) {
  Source a("A");
  EXPECT_EQ(a.out.fullName(), "A.out");
  EXPECT_EQ(a.events().fullName(), "A.events");
  InputPort<double> loose{"loose", "no owner", "m"};
  EXPECT_EQ(loose.fullName(), "loose");
  EXPECT_EQ(loose.owner(), nullptr);
  EXPECT_EQ(a.out.owner(), &a);
}

TEST(Port, DescribesItself) {
  Sink s("S");
  EXPECT_EQ(s.in.name(), "in");
  EXPECT_EQ(s.in.doc(), "value");
  EXPECT_EQ(s.in.unit(), "m");
  EXPECT_EQ(s.in.direction(), PortDirection::Input);
  EXPECT_EQ(s.in.type().name, "double");
  EXPECT_TRUE(s.in.isEventPort());
  EXPECT_FALSE(s.plain.isEventPort());
}

TEST(Port, TypedConnectCarriesData) {
  Source a("A");
  Sink b("B");
  connect(a.out, b.plain);
  EXPECT_TRUE(a.out.connected());
  EXPECT_TRUE(b.plain.connectedTo(a.out));
  EXPECT_TRUE(a.out.connectedTo(b.plain));
  EXPECT_EQ(a.out.write(1.5), WriteStatus::Written);
  double v = 0.0;
  EXPECT_EQ(b.plain.read(v), FlowStatus::NewData);
  EXPECT_EQ(v, 1.5);
  EXPECT_EQ(b.plain.read(v), FlowStatus::OldData);
}

TEST(Port, ConnectByNameThroughPortBase) {
  Source a("A");
  Sink b("B");
  connectPorts(a.port("out"), b.port("plain"), ConnPolicy::buffer(4));
  ASSERT_EQ(a.out.connections().size(), 1U);
  EXPECT_EQ(a.out.connections()[0]->policy(), ConnPolicy::buffer(4));
  EXPECT_EQ(&a.out.connections()[0]->reader(), &b.plain);
  for (double x : {1.0, 2.0, 3.0}) EXPECT_EQ(a.out.write(x), WriteStatus::Written);
  double v = 0.0;
  for (double x : {1.0, 2.0, 3.0}) {
    EXPECT_EQ(b.plain.read(v), FlowStatus::NewData);
    EXPECT_EQ(v, x);
  }
}

TEST(Port, WrongTypesAreRefusedNamingBothPortsAndTypes) {
  Source a("A");
  IntSink b("B");
  const std::string msg = messageOf([&] { connectPorts(a.out, b.in); });
  EXPECT_NE(msg.find("cannot connect A.out (double) to B.in (int)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("types differ"), std::string::npos) << msg;
  EXPECT_FALSE(a.out.connected());
  EXPECT_FALSE(b.in.connected());
}

TEST(Port, InputToInputIsRefused) {
  Sink a("A");
  Sink b("B");
  const std::string msg = messageOf([&] { connectPorts(a.plain, b.plain); });
  EXPECT_NE(msg.find("cannot connect A.plain (double) to B.plain (double)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("A.plain is an input port"), std::string::npos) << msg;
  EXPECT_FALSE(a.plain.connected());
}

TEST(Port, OutputToOutputIsRefused) {
  Source a("A");
  Source b("B");
  const std::string msg = messageOf([&] { connectPorts(a.out, b.out); });
  EXPECT_NE(msg.find("cannot connect A.out (double) to B.out (double)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("B.out is an output port"), std::string::npos) << msg;
  EXPECT_FALSE(a.out.connected());
  EXPECT_FALSE(b.out.connected());
}

TEST(Port, InputThenOutputIsRefusedAndNamesTheWrongOrder) {
  Source a("A");
  Sink b("B");
  const std::string msg = messageOf([&] { connectPorts(b.plain, a.out); });
  EXPECT_NE(msg.find("B.plain is an input port; the first port must be an output"), std::string::npos) << msg;
}

TEST(Port, DuplicateConnectionIsRefused) {
  Source a("A");
  Sink b("B");
  connect(a.out, b.plain);
  const std::string msg = messageOf([&] { connect(a.out, b.plain, ConnPolicy::buffer(2)); });
  EXPECT_NE(msg.find("cannot connect A.out (double) to B.plain (double)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("already connected"), std::string::npos) << msg;
  EXPECT_EQ(a.out.connections().size(), 1U);
}

TEST(Port, TooManyConnectionsAreRefused) {
  Source a("A");
  std::vector<std::unique_ptr<InputPort<double>>> readers;
  for (std::size_t i = 0; i < PortBase::kMaxConnections; ++i) {
    readers.push_back(std::make_unique<InputPort<double>>("r" + std::to_string(i), "", "m"));
    connect(a.out, *readers.back());
  }
  InputPort<double> extra{"extra", "", "m"};
  const std::string msg = messageOf([&] { connect(a.out, extra); });
  EXPECT_NE(msg.find("A.out already has 32 connections"), std::string::npos) << msg;
  EXPECT_EQ(a.out.write(4.0), WriteStatus::Written);
  double v = 0.0;
  EXPECT_EQ(readers.back()->read(v), FlowStatus::NewData);
  EXPECT_EQ(v, 4.0);
}

// --- data flow --------------------------------------------------------------------------------

TEST(Port, WriteWithoutConnectionsIsNotConnected) {
  Source a("A");
  EXPECT_EQ(a.out.write(1.0), WriteStatus::NotConnected);
  InputPort<double> in{"in", "", "m"};
  double v = 3.0;
  EXPECT_EQ(in.read(v), FlowStatus::NoData);
  EXPECT_EQ(v, 3.0);
}

TEST(Port, ManyReadersEachGetEverySample) {
  OutputPort<int> out{"out", "", "1"};
  InputPort<int> r1{"r1", "", "1"};
  InputPort<int> r2{"r2", "", "1"};
  InputPort<int> r3{"r3", "", "1"};
  connect(out, r1, ConnPolicy::buffer(16));
  connect(out, r2, ConnPolicy::buffer(16));
  connect(out, r3, ConnPolicy::circular(16));
  for (int i = 0; i < 10; ++i) ASSERT_EQ(out.write(i), WriteStatus::Written);
  for (InputPort<int>* r : {&r1, &r2, &r3}) {
    for (int i = 0; i < 10; ++i) {
      int v = -1;
      ASSERT_EQ(r->read(v), FlowStatus::NewData) << r->name() << " sample " << i;
      EXPECT_EQ(v, i);
    }
    int v = -1;
    EXPECT_EQ(r->read(v), FlowStatus::OldData);
    EXPECT_EQ(v, 9);
  }
}

// readNew: NewData copies the sample like read; OldData and NoData leave the output as it was
// (read copies the last sample again), for data and buffer connections alike.
TEST(Port, ReadNewCopiesOnlyNewSamples) {
  for (const ConnPolicy& policy : {ConnPolicy::data(), ConnPolicy::buffer(4)}) {
    OutputPort<int> out{"out", "", "1"};
    InputPort<int> in{"in", "", "1"};
    int v = -1;
    EXPECT_EQ(in.readNew(v), FlowStatus::NoData);
    connect(out, in, policy);
    EXPECT_EQ(in.readNew(v), FlowStatus::NoData);
    EXPECT_EQ(v, -1);
    ASSERT_EQ(out.write(7), WriteStatus::Written);
    EXPECT_EQ(in.readNew(v), FlowStatus::NewData);
    EXPECT_EQ(v, 7);
    v = -2;
    EXPECT_EQ(in.readNew(v), FlowStatus::OldData);
    EXPECT_EQ(v, -2);
    EXPECT_EQ(in.read(v), FlowStatus::OldData);
    EXPECT_EQ(v, 7);
  }
}

// An input that belongs to no component with a new-data flag: every write sets the flag, and a
// cleared flag stays clear while nothing is written; another reader's flag is not touched.
TEST(Port, ANewDataFlagIsSetByEveryWrite) {
  OutputPort<int> out{"out", "", "1"};
  InputPort<int> flagged{"flagged", "", "1"};
  InputPort<int> plain{"plain", "", "1"};
  std::atomic<bool> flag{false};
  flagged.setNewDataFlag(&flag);
  EXPECT_TRUE(flagged.isEventPort());
  connect(out, flagged, ConnPolicy::buffer(8));
  connect(out, plain, ConnPolicy::buffer(8));
  EXPECT_FALSE(flag.load());
  ASSERT_EQ(out.write(1), WriteStatus::Written);
  EXPECT_TRUE(flag.exchange(false));
  int v = 0;
  EXPECT_EQ(flagged.readNew(v), FlowStatus::NewData);
  EXPECT_FALSE(flag.load());
  ASSERT_EQ(out.write(2), WriteStatus::Written);
  ASSERT_EQ(out.write(3), WriteStatus::Written);
  EXPECT_TRUE(flag.exchange(false));
  EXPECT_EQ(flagged.readNew(v), FlowStatus::NewData);
  EXPECT_EQ(v, 2);
  EXPECT_EQ(flagged.readNew(v), FlowStatus::NewData);
  EXPECT_EQ(v, 3);
  EXPECT_FALSE(flag.load());
}

TEST(Port, AFullBufferReportsDroppedButOtherReadersStillGetTheSample) {
  OutputPort<int> out{"out", "", "1"};
  InputPort<int> small{"small", "", "1"};
  InputPort<int> latest{"latest", "", "1"};
  connect(out, small, ConnPolicy::buffer(1));
  connect(out, latest);
  EXPECT_EQ(out.write(1), WriteStatus::Written);
  EXPECT_EQ(out.write(2), WriteStatus::Dropped);
  int v = 0;
  EXPECT_EQ(latest.read(v), FlowStatus::NewData);
  EXPECT_EQ(v, 2);
  EXPECT_EQ(small.read(v), FlowStatus::NewData);
  EXPECT_EQ(v, 1);
}

TEST(Port, OneInputWithTwoWritersReadsBoth) {
  OutputPort<int> w1{"w1", "", "1"};
  OutputPort<int> w2{"w2", "", "1"};
  InputPort<int> in{"in", "", "1"};
  connect(w1, in, ConnPolicy::buffer(4));
  connect(w2, in, ConnPolicy::buffer(4));
  EXPECT_EQ(in.connections().size(), 2U);
  ASSERT_EQ(w2.write(20), WriteStatus::Written);
  int v = 0;
  EXPECT_EQ(in.read(v), FlowStatus::NewData);
  EXPECT_EQ(v, 20);
  ASSERT_EQ(w1.write(10), WriteStatus::Written);
  ASSERT_EQ(w2.write(21), WriteStatus::Written);
  std::vector<int> got;
  while (in.read(v) == FlowStatus::NewData) got.push_back(v);
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, (std::vector<int>{10, 21}));
  EXPECT_EQ(in.read(v), FlowStatus::OldData);
}

// An input whose connections are all buffered skips its scan until a writer pushes again; one
// with a data connection among them always scans. Either way every sample is read once.
TEST(Port, AnEmptyScanIsSkippedOnlyUntilTheNextWrite) {
  OutputPort<int> a{"a", "", "1"};
  OutputPort<int> b{"b", "", "1"};
  OutputPort<int> latest{"latest", "", "1"};
  InputPort<int> buffered{"buffered", "", "1"};
  InputPort<int> mixed{"mixed", "", "1"};
  connect(a, buffered, ConnPolicy::buffer(4));
  connect(b, buffered, ConnPolicy::circular(2));
  connect(a, mixed, ConnPolicy::buffer(4));
  connect(latest, mixed);
  int v = 0;
  EXPECT_EQ(buffered.readNew(v), FlowStatus::NoData);
  EXPECT_EQ(buffered.readNew(v), FlowStatus::NoData);
  ASSERT_EQ(b.write(7), WriteStatus::Written);
  EXPECT_EQ(buffered.read(v), FlowStatus::NewData);
  EXPECT_EQ(v, 7);
  EXPECT_EQ(buffered.read(v), FlowStatus::OldData);
  EXPECT_EQ(buffered.read(v), FlowStatus::OldData);
  EXPECT_EQ(v, 7);
  // Three writes into the circular connection of size 2: the oldest is overwritten.
  ASSERT_EQ(a.write(1), WriteStatus::Written);
  ASSERT_EQ(b.write(8), WriteStatus::Written);
  ASSERT_EQ(b.write(9), WriteStatus::Written);
  ASSERT_EQ(b.write(10), WriteStatus::Written);
  std::vector<int> got;
  while (buffered.readNew(v) == FlowStatus::NewData) got.push_back(v);
  EXPECT_EQ(got, (std::vector<int>{1, 9, 10}));
  EXPECT_EQ(buffered.readNew(v), FlowStatus::OldData);
  // The mixed input: the data connection is not counted, so it is always looked at.
  EXPECT_EQ(mixed.readNew(v), FlowStatus::NewData);  // a's 1
  EXPECT_EQ(v, 1);
  EXPECT_EQ(mixed.readNew(v), FlowStatus::OldData);
  ASSERT_EQ(latest.write(5), WriteStatus::Written);
  EXPECT_EQ(mixed.readNew(v), FlowStatus::NewData);
  EXPECT_EQ(v, 5);
  // Disconnecting the data connection makes the input count-driven; nothing is lost either way.
  ASSERT_TRUE(disconnectPorts(latest, mixed));
  EXPECT_EQ(mixed.readNew(v), FlowStatus::NoData);  // the connection last read from is gone
  ASSERT_EQ(a.write(2), WriteStatus::Written);
  EXPECT_EQ(mixed.readNew(v), FlowStatus::NewData);
  EXPECT_EQ(v, 2);
  EXPECT_EQ(buffered.readNew(v), FlowStatus::NewData);
  EXPECT_EQ(v, 2);
}

TEST(Port, DisconnectPortsRemovesOneConnection) {
  OutputPort<int> out{"out", "", "1"};
  InputPort<int> a{"a", "", "1"};
  InputPort<int> b{"b", "", "1"};
  connect(out, a);
  connect(out, b);
  EXPECT_TRUE(disconnectPorts(out, a));
  EXPECT_FALSE(disconnectPorts(out, a)) << "nothing left to disconnect";
  EXPECT_FALSE(a.connected());
  EXPECT_TRUE(b.connected());
  EXPECT_EQ(out.write(5), WriteStatus::Written);
  int v = 0;
  EXPECT_EQ(a.read(v), FlowStatus::NoData);
  EXPECT_EQ(b.read(v), FlowStatus::NewData);
  connect(out, a);  // can be connected again
  EXPECT_TRUE(a.connected());
}

TEST(Port, DisconnectRemovesEveryConnectionOfAPort) {
  OutputPort<int> out{"out", "", "1"};
  InputPort<int> a{"a", "", "1"};
  InputPort<int> b{"b", "", "1"};
  connect(out, a);
  connect(out, b);
  out.disconnect();
  EXPECT_FALSE(out.connected());
  EXPECT_FALSE(a.connected());
  EXPECT_FALSE(b.connected());
  EXPECT_EQ(out.write(1), WriteStatus::NotConnected);
}

TEST(Port, HasReadersFollowsTheConnections) {
  OutputPort<int> out{"out", "", "1"};
  InputPort<int> a{"a", "", "1"};
  InputPort<int> b{"b", "", "1"};
  EXPECT_FALSE(out.hasReaders());
  connect(out, a);
  connect(out, b);
  EXPECT_TRUE(out.hasReaders());
  EXPECT_TRUE(disconnectPorts(out, a));
  EXPECT_TRUE(out.hasReaders()) << "b still reads";
  b.disconnect();
  EXPECT_FALSE(out.hasReaders());
}

TEST(Port, DestroyingAPortDisconnectsItsPeers) {
  InputPort<int> in{"in", "", "1"};
  {
    OutputPort<int> out{"out", "", "1"};
    connect(out, in);
    ASSERT_TRUE(in.connected());
  }
  EXPECT_FALSE(in.connected());
  Source* peer = new Source("P");
  InputPort<Event> events{"events_in", "", ""};
  connect(peer->events(), events);
  delete peer;  // the events port is a member of Component itself
  EXPECT_FALSE(events.connected());
}

// --- event ports ------------------------------------------------------------------------------

TEST(Port, EventPortTriggersASlaveActivity) {
  Source a("A");
  Sink b("B");
  connect(a.out, b.in);
  connect(a.out, b.plain);
  auto& slave = dynamic_cast<SlaveActivity&>(b.activity());
  ASSERT_TRUE(b.configure());
  ASSERT_TRUE(b.start());
  EXPECT_FALSE(slave.triggered());
  ASSERT_EQ(a.out.write(2.0), WriteStatus::Written);
  EXPECT_TRUE(slave.triggered());
  slave.step();
  EXPECT_FALSE(slave.triggered());
  EXPECT_EQ(b.last.load(), 2.0);
  EXPECT_EQ(b.updateCount(), 1U);
  ASSERT_TRUE(b.stop());
}

TEST(Port, PlainInputPortDoesNotTrigger) {
  Source a("A");
  Sink b("B");
  connect(a.out, b.plain);
  ASSERT_EQ(a.out.write(2.0), WriteStatus::Written);
  EXPECT_FALSE(dynamic_cast<SlaveActivity&>(b.activity()).triggered());
}

TEST(Port, EventPortRunsAnEventActivityUpdateAfterAWrite) {
  Source a("A");
  Sink b("B");
  b.setActivity(std::make_unique<EventActivity>(50, Scheduler::Other));
  connect(a.out, b.in);
  ASSERT_TRUE(b.configure());
  ASSERT_TRUE(b.start());
  for (int i = 1; i <= 5; ++i) {
    ASSERT_EQ(a.out.write(10.0 * i), WriteStatus::Written);
    ASSERT_TRUE(waitUntil([&] { return b.updateCount() >= static_cast<std::uint64_t>(i); })) << "write " << i;
    EXPECT_EQ(b.last.load(), 10.0 * i);
  }
  EXPECT_EQ(b.updateCount(), 5U);
  ASSERT_TRUE(b.stop());
}

TEST(Port, ConnectingToARunningEventActivityComponentWorks) {
  Source a("A");
  Sink b("B");
  b.setActivity(std::make_unique<EventActivity>(50, Scheduler::Other));
  ASSERT_TRUE(b.configure());
  ASSERT_TRUE(b.start());
  connect(a.out, b.in);  // applied between two steps of B
  ASSERT_EQ(a.out.write(7.0), WriteStatus::Written);
  ASSERT_TRUE(waitUntil([&] { return b.last.load() == 7.0; }));
  EXPECT_TRUE(disconnectPorts(a.out, b.in));
  EXPECT_EQ(a.out.write(8.0), WriteStatus::NotConnected);
  ASSERT_TRUE(b.stop());
}

TEST(Port, TypeErasedReaderAndTextWrite) {
  OutputPort<KDL::Vector> out{"out", "a point", "m"};
  OutputPortBase& erased = out;
  std::unique_ptr<InputPortBase> reader = erased.makeReader("probe", "console probe");
  EXPECT_EQ(reader->type().name, "KDL.Vector");
  EXPECT_EQ(reader->unit(), "m");
  erased.connectTo(*reader, ConnPolicy::buffer(4));
  std::string text = "unchanged";
  EXPECT_EQ(reader->readText(text), FlowStatus::NoData);
  EXPECT_EQ(text, "");
  EXPECT_EQ(erased.writeText("[1, 2.5, -3]"), WriteStatus::Written);
  EXPECT_EQ(reader->readText(text), FlowStatus::NewData);
  EXPECT_EQ(text, "[1, 2.5, -3]");
  EXPECT_EQ(reader->readText(text), FlowStatus::OldData);
  try {
    erased.writeText("[1, 2]");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "port out is a KDL.Vector: cannot write \"[1, 2]\"; expected [x, y, z] in m");
  }
}

TEST(Port, TypeErasedWriterFeedsAnInput) {
  InputPort<double> in{"in", "a force", "N"};
  InputPortBase& erased = in;
  std::unique_ptr<OutputPortBase> writer = erased.makeWriter("console", "console writer");
  EXPECT_EQ(writer->type().name, "double");
  EXPECT_EQ(writer->unit(), "N");
  EXPECT_EQ(writer->direction(), PortDirection::Output);
  writer->connectTo(in, ConnPolicy::data());
  EXPECT_EQ(writer->writeText("2.5"), WriteStatus::Written);
  double value = 0.0;
  EXPECT_EQ(in.read(value), FlowStatus::NewData);
  EXPECT_EQ(value, 2.5);
  writer.reset();  // destroying the writer disconnects it
  EXPECT_FALSE(in.connected());
}

}  // namespace
}  // namespace cobra::core
