#include "cobra/deploy/install_layout.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;
using cobra::deploy::dataDirectory;
using cobra::deploy::installedPackageDirectory;

namespace {

/// A temporary installation prefix: bin/cobra (not created; only its folder matters).
class Prefix : public ::testing::Test {
 protected:
  Prefix() : prefix_(fs::temp_directory_path() / ("cobra_install_layout_" + std::to_string(::getpid()))) {
    fs::create_directories(prefix_ / "bin");
    ::unsetenv("COBRA_DATA_DIR");
  }
  ~Prefix() override { fs::remove_all(prefix_); }
  fs::path tool() const { return prefix_ / "bin" / "cobra"; }
  fs::path prefix_;
};

}  // namespace

TEST_F(Prefix, NothingIsFoundWhenThePrefixHasNoData) {
  EXPECT_EQ(dataDirectory(tool()), fs::path());
  EXPECT_EQ(installedPackageDirectory(tool()), fs::path());
}

TEST_F(Prefix, DataAndPackagesAreFoundRelativeToTheTool) {
  fs::create_directories(prefix_ / "share" / "cobra" / "charts");
  fs::create_directories(prefix_ / "lib" / "cobra" / "packages");
  EXPECT_EQ(dataDirectory(tool()), prefix_ / "share" / "cobra");
  EXPECT_EQ(installedPackageDirectory(tool()), prefix_ / "lib" / "cobra" / "packages");
}

TEST_F(Prefix, TheEnvironmentChoosesTheDataFolder) {
  fs::create_directories(prefix_ / "share" / "cobra");
  ::setenv("COBRA_DATA_DIR", "/opt/elsewhere/share/cobra", 1);
  EXPECT_EQ(dataDirectory(tool()), fs::path("/opt/elsewhere/share/cobra"));
  ::unsetenv("COBRA_DATA_DIR");
}

TEST(InstallLayout, TheRunningExecutableIsThisTest) {
  EXPECT_EQ(cobra::deploy::runningExecutable().filename(), "deploy_install_layout_test");
}
