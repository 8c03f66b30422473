// One application split over two hosts, both in this process: two Configurators, each with its
// own host of one placement and its own DDS participant (two registered dds transports on one
// domain, as two processes would have). A signal made on host a (Sine, on the lockstep clock) is
// amplified and recorded on host b (Gain, Recorder, threaded): the placement's writer and reader
// ends carry every sample, in order.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <thread>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/signal/recorder.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/deploy/configurator.hpp"
#include "cobra/dds/dds_transport.hpp"

using namespace cobra;
using namespace std::chrono_literals;
using deploy::Configurator;
using deploy::PlacementSpec;
using deploy::SourceLocation;

namespace {

constexpr int kDomain = 141;  // this test's own DDS domain

SourceLocation at(int line) { return {"split.lua", line}; }

/// The same application files as each host sees them: Sine on host a, Gain and Rec on host b.
void deploySplit(Configurator& c, const std::string& transport) {
  components::addBuiltinPackages(c.packages());
  PlacementSpec placement;
  placement.hosts = {{"a", {"Sine"}, at(2)}, {"b", {"Gain", "Rec"}, at(3)}};
  placement.transport = transport;  // one participant per host
  placement.where = at(1);
  c.setPlacement(placement);
  c.initConfigurator({{"cobra_signal", at(5)}},
                     {{"Sine", "SineGenerator", at(6)}, {"Gain", "Gain", at(7)}, {"Rec", "Recorder", at(8)}});
  c.setActivities({{"Sine", 0.001, 0, "other", at(10)}});
  c.connectPorts({{"Sine.out", "Gain.in", {"buffer", 64}, at(12)}, {"Gain.out", "Rec.in", {"buffer", 64}, at(13)}});
  const std::vector<deploy::NameEntry> all{{"Sine", at(15)}, {"Gain", at(15)}, {"Rec", at(15)}};
  c.configureComponents(all);
  c.startComponents(all);
}

deploy::ConfiguratorOptions options(const std::string& host, deploy::ClockMode mode) {
  deploy::ConfiguratorOptions o;
  o.host = host;
  o.mode = mode;
  return o;
}

}  // namespace

TEST(PlacementOverDds, EverySampleOfHostAReachesHostBInOrder) {
  const auto dds_a = dds::registerDdsTransport({kDomain, "split_a", false}, "dds_split_a");
  const auto dds_b = dds::registerDdsTransport({kDomain, "split_b", false}, "dds_split_b");
  {
    Configurator a(options("a", deploy::ClockMode::Simulation));
    Configurator b(options("b", deploy::ClockMode::RealTime));
    deploySplit(a, "dds_split_a");
    deploySplit(b, "dds_split_b");
    EXPECT_EQ(a.writerTopics(), std::vector<std::string>{"Sine/out"});
    EXPECT_TRUE(a.readerTopics().empty());
    EXPECT_EQ(b.readerTopics(), std::vector<std::string>{"Sine/out"});
    EXPECT_EQ(a.getReferences().find("Rec"), nullptr);
    ASSERT_TRUE(dds_a->waitForMatch("Sine/out", 5s));
    ASSERT_TRUE(dds_b->waitForMatch("Sine/out", 5s));
    a.getReferences().get("Sine").setProperty("frequency", 50.0);
    b.getReferences().get("Gain").setProperty("k", 3.0);

    a.clock().advance(20ms);  // 20 samples, one per ms
    // The recorder's samples are read while it is stopped (recorder.hpp); it runs again between looks.
    const auto& rec = dynamic_cast<const components::Recorder&>(b.getReferences().get("Rec"));
    for (int look = 0; look < 500; ++look) {
      std::this_thread::sleep_for(10ms);
      b.stopComponents({{"Rec", at(20)}});
      if (rec.samples().size() >= 20) break;
      b.startComponents({{"Rec", at(20)}});
    }
    ASSERT_EQ(rec.samples().size(), 20u);
    for (std::size_t i = 0; i < 20; ++i) {
      const double t = 1e-3 * static_cast<double>(i);
      EXPECT_NEAR(rec.samples()[i].value, 3.0 * std::sin(2 * std::numbers::pi * 50.0 * t), 1e-12) << "sample " << i;
    }
  }
  core::TransportRegistry::remove("dds_split_a");
  core::TransportRegistry::remove("dds_split_b");
}
