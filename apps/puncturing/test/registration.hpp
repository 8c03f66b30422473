#pragma once
// A scenario registered off its nominal pose, for the procedure tests (procedure_slow_test.cpp,
// registration_sweep_test.cpp): a copy of the scenario whose preoperative `abdomen` line is
// rewritten. Every file that places the phantom (the Patient, the planner's phantom, the Frame
// Generators, the monitors' forbidden regions) reads that line, so the whole setup moves with it.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <unistd.h>

#include <kdl/frames.hpp>

#include "procedure_expectations.hpp"

namespace cobra::run::testing {

/// A copy of scenario `name` (in a folder named after `tag` and this process) whose abdomen pose
/// A (m, rad, task frame) is replaced by `move(A)`.
inline std::filesystem::path registered(const std::string& name, const std::string& tag,
                                        const std::function<KDL::Frame(const KDL::Frame&)>& move) {
  const std::filesystem::path from = kApp / "scenarios" / name;
  // Per process: other checkouts may run the same test at the same time.
  const std::filesystem::path to = std::filesystem::temp_directory_path() /
                                   ("cobra_registration_" + name + "_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(to);
  std::filesystem::create_directories(to);
  for (const auto& file : std::filesystem::directory_iterator(from))
    std::filesystem::copy(file.path(), to / file.path().filename());
  std::ifstream in(from / "preoperative.txt");
  std::ostringstream out;
  bool moved = false;
  for (std::string line; std::getline(in, line);) {
    double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
    if (std::sscanf(line.c_str(), "abdomen xyz=%lf,%lf,%lf rpy=%lf,%lf,%lf", &x, &y, &z, &roll, &pitch, &yaw) == 6) {
      const KDL::Frame a = move(KDL::Frame(KDL::Rotation::RPY(roll, pitch, yaw), KDL::Vector(x, y, z)));
      a.M.GetRPY(roll, pitch, yaw);
      char text[240];
      std::snprintf(text, sizeof text, "abdomen xyz=%.6f,%.6f,%.6f rpy=%.6f,%.6f,%.6f  # %s", a.p.x(), a.p.y(), a.p.z(),
                    roll, pitch, yaw, tag.c_str());
      line = text;
      moved = true;
    }
    out << line << "\n";
  }
  EXPECT_TRUE(moved) << from / "preoperative.txt" << " has no `abdomen xyz=X,Y,Z rpy=R,P,Y` line";
  std::ofstream(to / "preoperative.txt") << out.str();
  return to;
}

}  // namespace cobra::run::testing
