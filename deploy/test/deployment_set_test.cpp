#include "cobra/deploy/deployment_set.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "cobra/core/error.hpp"
#include "cobra/test_support/test_support.hpp"

using namespace cobra;
using deploy::DeploymentSet;
using deploy::SourceLocation;
using ::testing::HasSubstr;
using test_support::messageOf;

namespace {

std::filesystem::path freshFolder(const std::string& name) {
  const auto folder = ::cobra::test_support::scratchPath(name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

}  // namespace

TEST(DeploymentSet, NamesAreUniqueAndLookupsSuggestTheClosest) {
  DeploymentSet set;
  set.addDeployment({"approach", {"a.lua", 1}, {}, {}, {}});
  set.addDeployment({"puncture", {"p.lua", 1}, {}, {}, {}});
  set.addConfiguration({"stiff", {"stiff.cfg", 1}, {}});
  EXPECT_THAT(messageOf([&] { set.addDeployment({"approach", {"b.lua", 7}, {}, {}, {}}); }),
              HasSubstr("b.lua:7: a deployment named 'approach' already exists (a.lua:1)"));
  EXPECT_THAT(messageOf([&] { set.addConfiguration({"stiff", {"other.cfg", 1}, {}}); }),
              HasSubstr("other.cfg:1: a configuration named 'stiff' already exists (stiff.cfg:1)"));
  EXPECT_THAT(messageOf([&] { (void)set.deployment("punctur"); }),
              HasSubstr("no deployment named 'punctur'; did you mean 'puncture'? known deployments: approach, puncture"));
  EXPECT_THAT(messageOf([&] { (void)set.configuration("soft"); }),
              HasSubstr("no configuration named 'soft'; known configurations: stiff"));
  EXPECT_EQ(set.deploymentNames(), (std::vector<std::string>{"approach", "puncture"}));
  EXPECT_EQ(set.findConfiguration("stiff")->where.file, "stiff.cfg");
}

TEST(DeploymentSet, ConfigurationFilesGiveEveryValueItsLine) {
  const auto folder = freshFolder("cobra_deploy_configurations");
  std::ofstream(folder / "stiff.cfg") << "# a stiff admittance\n\nAdm.stiffness = 2000\n  Adm.damping=  40.5  \n"
                                      << "Planner.goal = [0, 0.1, 0.2]\n";
  std::ofstream(folder / "soft.cfg") << "Adm.stiffness = 200\n";
  std::ofstream(folder / "notes.txt") << "not a configuration\n";
  const auto loaded = deploy::loadConfigurationFolder(folder);
  ASSERT_EQ(loaded.size(), 2u);
  EXPECT_EQ(loaded[0].name, "soft");
  const auto& stiff = loaded[1];
  EXPECT_EQ(stiff.name, "stiff");
  ASSERT_EQ(stiff.values.size(), 3u);
  EXPECT_EQ(stiff.values[0].component, "Adm");
  EXPECT_EQ(stiff.values[0].property, "stiffness");
  EXPECT_EQ(stiff.values[0].value, "2000");
  EXPECT_EQ(stiff.values[0].where, (SourceLocation{(folder / "stiff.cfg").string(), 3}));
  EXPECT_EQ(stiff.values[1].value, "40.5");
  EXPECT_EQ(stiff.values[1].where.line, 4);
  EXPECT_EQ(stiff.values[2].value, "[0, 0.1, 0.2]");
}

TEST(DeploymentSet, MalformedConfigurationLinesAreReportedWithTheirLine) {
  const auto folder = freshFolder("cobra_deploy_bad_lines");
  std::ofstream(folder / "bad.cfg") << "Adm.stiffness = 1\nstiffness = 2\n";
  EXPECT_THAT(messageOf([&] { (void)deploy::loadConfigurationFolder(folder); }),
              HasSubstr((folder / "bad.cfg").string() + ":2: expected \"Component.property = value\", got "
                                                        "\"stiffness = 2\""));
  EXPECT_THAT(messageOf([&] { (void)deploy::loadConfigurationFolder(folder / "missing"); }),
              HasSubstr("does not exist or is not a folder"));
}

TEST(Spec, LocationsPortPathsPoliciesAndSchedulers) {
  EXPECT_EQ((SourceLocation{"deploy.lua", 12}.text()), "deploy.lua:12");
  EXPECT_EQ((SourceLocation{"deploy.lua", 0}.text()), "deploy.lua");
  EXPECT_EQ(SourceLocation{}.text(), "<no location>");
  const auto path = deploy::parsePortPath("MotPlan.path", {});
  EXPECT_EQ(path.component, "MotPlan");
  EXPECT_EQ(path.port, "path");
  EXPECT_THAT(messageOf([] { (void)deploy::parsePortPath("MotPlan.", {"d.lua", 3}); }),
              HasSubstr("d.lua:3: 'MotPlan.' is not a port path"));
  EXPECT_EQ(deploy::toConnPolicy({"data", 7}, {}), core::ConnPolicy::data());
  EXPECT_EQ(deploy::toConnPolicy({"BUFFER", 8}, {}), core::ConnPolicy::buffer(8));
  EXPECT_EQ(deploy::toConnPolicy({"circular_buffer", 2}, {}), core::ConnPolicy::circular(2));
  EXPECT_THAT(messageOf([] { (void)deploy::toConnPolicy({"buffer", 0}, {"d.lua", 4}); }),
              HasSubstr("d.lua:4: a buffer connection needs size >= 1, got 0"));
  EXPECT_EQ(deploy::toScheduler("ORO_SCHED_RT", {}), core::Scheduler::Fifo);
  EXPECT_EQ(deploy::toScheduler("sched_other", {}), core::Scheduler::Other);
  EXPECT_THAT(messageOf([] { (void)deploy::toScheduler("realtime", {"d.lua", 5}); }),
              HasSubstr("d.lua:5: unknown scheduler 'realtime'"));
  EXPECT_TRUE((deploy::ActivitySpec{"A", 0.001, 80, "ORO_SCHED_RT", {"a.lua", 1}}.sameActivity(
      deploy::ActivitySpec{"A", 0.001, 80, "oro_sched_rt", {"b.lua", 9}})));
}
