// The transport extension point: a registry of named transports, connections whose two ends a
// transport makes (each an ordinary channel to a port the end owns), connectedTo and
// disconnectPorts across both ends, ends closed before their channel goes, nothing half-made
// when an end fails. The transport here is a loopback that carries samples in their text form
// when the test pumps it: core needs no real transport to be tested.
#include "cobra/core/transport.hpp"

#include <gtest/gtest.h>

#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::core {
namespace {

using test_support::messageOf;

class Loopback final : public Transport {
 public:
  struct End final : TransportEnd {
    std::string topic;
    std::unique_ptr<InputPortBase> from_port;  // writer's end
    std::unique_ptr<OutputPortBase> to_port;   // reader's end
    int* closes = nullptr;
    void close() noexcept override { ++*closes; }
  };

  void check(const ConnPolicy& policy) const override {
    if (policy.topic.empty()) throw Error("a loopback connection needs a topic");
    for (const auto& [key, value] : policy.options)
      if (key != "fail_writer") throw Error("unknown loopback option '" + key + "'; allowed: fail_writer");
  }
  void makeWriterEnd(OutputPortBase& output, const ConnPolicy& policy, PortBase* peer) override {
    if (!policy.options.empty()) throw Error("the writer's end failed, as asked");
    auto end = makeEnd(policy);
    end->from_port = output.makeReader("loop", "");
    attachTransportEnd(output, *end->from_port, policy, end, peer);
  }
  void makeReaderEnd(InputPortBase& input, const ConnPolicy& policy, PortBase* peer) override {
    auto end = makeEnd(policy);
    end->to_port = input.makeWriter("loop", "");
    attachTransportEnd(input, *end->to_port, policy, end, peer);
  }

  /// Carries every unread sample of the writers' ends to the readers' ends of the same topic.
  void pump() {
    for (const auto& weak_writer : ends_) {
      auto writer = weak_writer.lock();
      if (!writer || !writer->from_port) continue;
      std::string text;
      while (writer->from_port->readText(text) == FlowStatus::NewData)
        for (const auto& weak_reader : ends_)
          if (auto reader = weak_reader.lock(); reader && reader->to_port && reader->topic == writer->topic)
            reader->to_port->writeText(text);
    }
  }
  std::size_t liveEnds() const {
    return static_cast<std::size_t>(std::count_if(ends_.begin(), ends_.end(), [](const auto& e) { return !e.expired(); }));
  }
  int closes = 0;

 private:
  std::shared_ptr<End> makeEnd(const ConnPolicy& policy) {
    auto end = std::make_shared<End>();
    end->topic = policy.topic;
    end->closes = &closes;
    ends_.push_back(end);
    return end;
  }
  std::vector<std::weak_ptr<End>> ends_;
};

struct Registered {
  Registered() { TransportRegistry::add("loop", "loopback for tests", "transport_test", loop); }
  ~Registered() { TransportRegistry::remove("loop"); }
  std::shared_ptr<Loopback> loop = std::make_shared<Loopback>();
};

ConnPolicy over(const std::string& topic, ConnPolicy policy = ConnPolicy::data()) {
  policy.transport = "loop";
  policy.topic = topic;
  return policy;
}

TEST(Transport, ConnectPortsMakesBothEndsAndTheSamplesGoThroughTheTransport) {
  Registered r;
  OutputPort<double> out("out", "", "m");
  InputPort<double> in("in", "", "m");
  connectPorts(out, in, over("x", ConnPolicy::buffer(4)));
  EXPECT_TRUE(out.connectedTo(in));
  EXPECT_TRUE(in.connectedTo(out));
  EXPECT_EQ(r.loop->liveEnds(), 2U);
  EXPECT_EQ(out.connections().front()->policy().describe(), "buffer(4) over loop topic 'x'");

  double got = 0;
  out.write(1.5);
  out.write(2.5);
  EXPECT_EQ(in.read(got), FlowStatus::NoData);  // nothing crossed yet: the transport carries it
  r.loop->pump();
  EXPECT_EQ(in.read(got), FlowStatus::NewData);
  EXPECT_EQ(got, 1.5);
  EXPECT_EQ(in.read(got), FlowStatus::NewData);
  EXPECT_EQ(got, 2.5);
  EXPECT_EQ(in.read(got), FlowStatus::OldData);
  EXPECT_THROW(connectPorts(out, in, over("x")), Error);  // already connected
}

TEST(Transport, DisconnectPortsClosesAndEndsBothEnds) {
  Registered r;
  OutputPort<double> out("out", "", "m");
  InputPort<double> in("in", "", "m");
  connect(out, in, over("x"));  // the typed connect honours the transport too
  ASSERT_EQ(r.loop->liveEnds(), 2U);
  EXPECT_TRUE(disconnectPorts(out, in));
  EXPECT_EQ(r.loop->closes, 2);
  EXPECT_EQ(r.loop->liveEnds(), 0U);
  EXPECT_FALSE(out.connected());
  EXPECT_FALSE(in.connected());
  EXPECT_EQ(out.write(1.0), WriteStatus::NotConnected);
  EXPECT_FALSE(disconnectPorts(out, in));
}

TEST(Transport, DestroyingAPortEndsItsEnd) {
  Registered r;
  InputPort<double> in("in", "", "m");
  {
    OutputPort<double> out("out", "", "m");
    connectToTransport(out, over("x"));
    connectToTransport(in, over("x"));
    EXPECT_FALSE(out.connectedTo(in));  // two separate ends: their peer is elsewhere
    out.write(3.0);
    r.loop->pump();
    double got = 0;
    EXPECT_EQ(in.read(got), FlowStatus::NewData);
    EXPECT_EQ(got, 3.0);
  }
  EXPECT_EQ(r.loop->closes, 1);
  EXPECT_EQ(r.loop->liveEnds(), 1U);
  in.disconnect();
  EXPECT_EQ(r.loop->liveEnds(), 0U);
}

TEST(Transport, AFailingEndLeavesNothingConnected) {
  Registered r;
  OutputPort<double> out("out", "", "m");
  InputPort<double> in("in", "", "m");
  ConnPolicy policy = over("x");
  policy.options = {{"fail_writer", "yes"}};
  EXPECT_EQ(messageOf([&] { connectPorts(out, in, policy); }),
            "cannot connect out (double) to in (double): the writer's end failed, as asked");
  EXPECT_FALSE(out.connected());
  EXPECT_FALSE(in.connected());  // the reader's end made first was removed
  EXPECT_EQ(r.loop->liveEnds(), 0U);
}

TEST(Transport, UnknownTransportsAndBadOptionsAreNamed) {
  Registered r;
  OutputPort<double> out("out", "", "m");
  InputPort<int> other("other", "", "1");
  ConnPolicy unknown = over("x");
  unknown.transport = "zmq";
  EXPECT_EQ(messageOf([&] { connectToTransport(out, unknown); }),
            "cannot connect out (double) to zmq topic 'x': unknown transport 'zmq'; transports: 'loop' (loopback for "
            "tests, from transport_test)");
  ConnPolicy bad = over("x");
  bad.options = {{"speed", "fast"}};
  EXPECT_EQ(messageOf([&] { connectToTransport(out, bad); }),
            "cannot connect out (double) to loop topic 'x': unknown loopback option 'speed'; allowed: fail_writer");
  EXPECT_EQ(messageOf([&] { connectPorts(out, other, over("x")); }),
            "cannot connect out (double) to other (int): the types differ (double vs int); connect ports of the same "
            "type");
  EXPECT_NE(messageOf([&] { connectToTransport(out, ConnPolicy::data()); }).find("its connection policy names none"),
            std::string::npos);
}

TEST(Transport, TheRegistryChecksNamesAndOwners) {
  Registered r;
  EXPECT_EQ(TransportRegistry::names(), std::vector<std::string>{"loop"});
  EXPECT_EQ(messageOf([&] { TransportRegistry::add("loop", "another", "someone_else", std::make_shared<Loopback>()); }),
            "someone_else registers the transport 'loop', which transport_test registered already; transport names "
            "must be unique");
  TransportRegistry::add("loop", "loopback again", "transport_test", r.loop);  // same owner: replaced
  EXPECT_EQ(messageOf([&] { TransportRegistry::add("a b", "", "x", std::make_shared<Loopback>()); }),
            "transport name 'a b' (from x): expected letters, digits, '_' or '-', as in 'dds'");
  EXPECT_TRUE(TransportRegistry::remove("loop"));
  EXPECT_FALSE(TransportRegistry::remove("loop"));
  EXPECT_EQ(messageOf([] { (void)TransportRegistry::get("loop"); }),
            "unknown transport 'loop'; transports: none are registered (a library registers its transport when it "
            "loads, e.g. cobra_dds)");
}

}  // namespace
}  // namespace cobra::core
