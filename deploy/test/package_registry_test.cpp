#include "cobra/components/signal/package.hpp"
#include "cobra/deploy/package_registry.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>

#include "cobra/core/core.hpp"
#include "cobra/test_support/test_support.hpp"
#include "test_components.hpp"

using namespace cobra;
using namespace std::chrono_literals;
using deploy::PackageRegistry;
using deploy::SourceLocation;
using ::testing::HasSubstr;
using test_support::messageOf;

TEST(PackageRegistry, ABuiltInPackageRegistersItsTypesWhenLoaded) {
  PackageRegistry registry;
  EXPECT_EQ(registry.knownPackages(), std::vector<std::string>{}) << "the deployer has no component package of its own";
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  EXPECT_EQ(registry.findType("Gain"), nullptr) << "types appear only once their package is loaded";
  registry.load("cobra_signal");
  EXPECT_TRUE(registry.isLoaded("cobra_signal"));
  EXPECT_EQ(registry.typeNames(), (std::vector<std::string>{"Constant", "Gain", "Recorder", "SineGenerator", "ThresholdDetector"}));
  auto gain = registry.create("Gain", "G");
  EXPECT_EQ(gain->name(), "G");
  EXPECT_EQ(gain->role(), core::Role::Calculation);
  EXPECT_EQ(registry.type("Gain").package, "cobra_signal");
  registry.load("cobra_signal");  // loading again does nothing
  EXPECT_EQ(registry.loadedPackages().size(), 1u);
}

TEST(PackageRegistry, UnknownPackageNamesTheClosestOnesAndTheSearchPath) {
  PackageRegistry registry({COBRA_TEST_PACKAGE_DIR});
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  const std::string message = messageOf([&] { registry.load("cobra_signl", {"deploy.lua", 3}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:3: unknown package 'cobra_signl'; did you mean 'cobra_signal'?"));
  EXPECT_THAT(message, HasSubstr("known packages: cobra_signal, cobra_test_filters, cobra_test_old_abi"));
  EXPECT_THAT(message, HasSubstr("libcobra_signl.so"));
  EXPECT_THAT(message, HasSubstr(COBRA_TEST_PACKAGE_DIR));
  EXPECT_THAT(message, HasSubstr("COBRA_PACKAGE_PATH"));
}

TEST(PackageRegistry, UnknownComponentTypeSuggestsTheClosestName) {
  PackageRegistry registry;
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  registry.load("cobra_signal");
  const std::string message = messageOf([&] { (void)registry.create("Gian", "G", {"deploy.lua", 12}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:12: unknown component type 'Gian'; did you mean 'Gain'? known types: "
                                 "Constant, Gain, Recorder, SineGenerator, ThresholdDetector"));
  EXPECT_THAT(message, HasSubstr("loaded packages: cobra_signal"));
}

TEST(PackageRegistry, SharedLibraryPackageLoadsAndItsComponentsRun) {
  PackageRegistry registry({COBRA_TEST_PACKAGE_DIR});
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  registry.load("cobra_signal");
  registry.load("cobra_test_filters", {"deploy.lua", 2});
  ASSERT_NE(registry.findType("Offset"), nullptr);
  EXPECT_EQ(registry.type("Offset").package, "cobra_test_filters");

  core::ComponentRegistry components;
  auto& offset = components.add(registry.create("Offset", "Off"));
  auto& gain = components.add(registry.create("Gain", "Gain"));
  offset.setProperty("offset", 10.0);
  core::OutputPort<double> source{"source", "test input", "1"};
  core::InputPort<double> sink{"sink", "test output", "1"};
  core::connectPorts(source, offset.port("in"), core::ConnPolicy::buffer(4));
  core::connectPorts(offset.port("out"), gain.port("in"), core::ConnPolicy::buffer(4));
  core::connectPorts(gain.port("out"), sink, core::ConnPolicy::buffer(4));
  gain.setProperty("k", 2.0);
  core::LockstepClock clock;
  clock.add(offset, 0ns);
  clock.add(gain, 0ns);
  for (core::Component* c : components.components()) {
    ASSERT_TRUE(c->configure());
    ASSERT_TRUE(c->start());
  }
  source.write(1.5);
  clock.advance(1ms);
  double out = 0.0;
  ASSERT_EQ(sink.read(out), core::FlowStatus::NewData);
  EXPECT_DOUBLE_EQ(out, 23.0);  // (1.5 + 10) * 2
}

TEST(PackageRegistry, SearchPathComesFromTheEnvironmentToo) {
  ::setenv("COBRA_PACKAGE_PATH", "/nonexistent/dir:" COBRA_TEST_PACKAGE_DIR, 1);
  PackageRegistry registry;
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  ::unsetenv("COBRA_PACKAGE_PATH");
  EXPECT_EQ(registry.searchPath().size(), 2u);
  registry.load("cobra_test_filters");
  EXPECT_NE(registry.findType("Offset"), nullptr);
}

TEST(PackageRegistry, PackageBuiltForAnotherAbiIsRefused) {
  PackageRegistry registry({COBRA_TEST_PACKAGE_DIR});
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  const std::string message = messageOf([&] { registry.load("cobra_test_old_abi", {"deploy.lua", 4}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:4: package 'cobra_test_old_abi'"));
  EXPECT_THAT(message, HasSubstr("was built for package ABI " + std::to_string(deploy::kPackageAbiVersion + 1) +
                                 ", this cobra has ABI " + std::to_string(deploy::kPackageAbiVersion)));
  EXPECT_THAT(message, HasSubstr("rebuild the package"));
  EXPECT_FALSE(registry.isLoaded("cobra_test_old_abi"));
}

TEST(PackageRegistry, PackageRegisteringAnExistingTypeRegistersNothing) {
  PackageRegistry registry;
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  registry.load("cobra_signal");
  registry.addBuiltin("clash", [](deploy::PackageBuilder& p) {
    p.component<deploy::test::Faulty>("Faulty", "first").component<deploy::test::Faulty>("Gain", "clashes");
  });
  const std::string message = messageOf([&] { registry.load("clash", {"deploy.lua", 5}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:5: package 'clash' failed to register its components: package 'clash' "
                                 "registers component type 'Gain', which package 'cobra_signal' already registered"));
  EXPECT_EQ(registry.findType("Faulty"), nullptr) << "a failed load must register nothing";
  EXPECT_FALSE(registry.isLoaded("clash"));
}

TEST(PackageRegistry, ConstructorErrorsNameTheInstanceAndType) {
  PackageRegistry registry;
  registry.addBuiltin("cobra_signal", components::registerSignalPackage);
  registry.load("cobra_signal");
  const std::string message = messageOf([&] { (void)registry.create("Gain", "bad name", {"deploy.lua", 9}); });
  EXPECT_THAT(message, HasSubstr("deploy.lua:9: cannot create 'bad name' of type 'Gain': component name 'bad name' "
                                 "may not contain '.' or spaces"));
}
