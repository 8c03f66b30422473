#include "chain_robot.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "cobra/kinematics/puma260.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "read_property.hpp"

namespace cobra::studio {
namespace {

constexpr std::size_t kDhValuesPerJoint = 7;  // a, alpha, d, theta, type, lower, upper (the component's dh_table)
constexpr double kShortestLeg = 1e-3;         // m: legs shorter than this are not drawn

// The DH rows the component's `robot` names, as its configureHook builds them.
std::vector<kinematics::DhRow> rowsOf(const core::ComponentRegistry& registry, const std::string& component,
                                      const std::string& where, const std::string& use) {
  const std::string robot = readProperty<std::string>(registry, component + ".robot", where, use,
                                                      "string (a KinematicsSolver's robot: puma260, ur5 or dh)");
  std::unique_ptr<kinematics::KinematicsSolver> solver;
  if (robot == "puma260") solver = kinematics::makePuma260Solver(kinematics::SolverKind::ClosedForm);
  if (robot == "ur5") solver = kinematics::makeUr5Solver(kinematics::SolverKind::ClosedForm);
  if (const auto* dh = dynamic_cast<const kinematics::DhAnalyticSolver*>(solver.get())) return dh->model().rows();
  if (robot != "dh")
    throw std::runtime_error(where + ": " + use + ": " + component + ".robot is '" + robot +
                             "'; cobra studio draws puma260, ur5 or dh (the dh_table)");
  const auto table = readProperty<std::vector<double>>(registry, component + ".dh_table", where, use,
                                                       "vector<double> (a, alpha, d, theta, type, lower, upper per joint)");
  if (table.empty() || table.size() % kDhValuesPerJoint != 0)
    throw std::runtime_error(where + ": " + use + ": " + component + ".dh_table has " + std::to_string(table.size()) +
                             " numbers; expected 7 per joint (a, alpha, d, theta, type, lower, upper)");
  std::vector<kinematics::DhRow> rows(table.size() / kDhValuesPerJoint);
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const double* v = &table[j * kDhValuesPerJoint];
    rows[j] = {v[0], v[1], v[2], v[3], v[4] == 0.0 ? kinematics::JointType::Revolute : kinematics::JointType::Prismatic,
               v[5], v[6]};
  }
  return rows;
}

// A cylinder of `radius` from `from` to `to` (m, in link `link`'s frame of `robot`).
planning::ObjectDescription leg(const std::string& robot, const std::string& name, std::size_t link,
                                const KDL::Vector& from, const KDL::Vector& to, double radius) {
  planning::ObjectDescription o;
  o.name = name;
  o.group = robot;
  o.attached_to = {robot, link};
  o.shape.kind = planning::ShapeKind::Cylinder;
  KDL::Vector axis = to - from;
  const double length = axis.Normalize();
  o.shape.dimensions = {radius, length, 0.0};
  // The rotation turning z onto the leg's axis (a cylinder lies along its frame's z).
  const KDL::Vector z(0.0, 0.0, 1.0), normal = z * axis;
  const double turn = std::atan2(normal.Norm(), KDL::dot(z, axis));
  const KDL::Rotation r = normal.Norm() > 1e-9 ? KDL::Rotation::Rot(normal, turn)
                                                : (turn > 1.0 ? KDL::Rotation::RotX(M_PI) : KDL::Rotation::Identity());
  o.offset = KDL::Frame(r, (from + to) / 2.0);
  return o;
}

}  // namespace

kinematics::SerialChainModel kinematicsChain(const core::ComponentRegistry& registry, const std::string& component,
                                             const std::string& where, const std::string& use) {
  std::vector<kinematics::DhRow> rows = rowsOf(registry, component, where, use);
  const auto base = readProperty<KDL::Frame>(registry, component + ".base_frame", where, use, "KDL.Frame (the robot's base, m)");
  const auto tool = readProperty<KDL::Frame>(registry, component + ".tool_frame", where, use, "KDL.Frame (the tool, m)");
  try {
    return kinematics::SerialChainModel(component, std::move(rows), base, tool);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(where + ": " + use + ": " + e.what());
  }
}

std::vector<planning::ObjectDescription> chainShapes(const std::string& robot, const kinematics::SerialChainModel& chain) {
  // Drawn sizes, not the robot's: 2.5 % of its reach, the housings 1.4 times thicker.
  const double radius = std::clamp(0.025 * chain.reachBound(), 0.005, 0.05), housing = 1.4 * radius;
  std::vector<planning::ObjectDescription> shapes;
  const auto add = [&](planning::ObjectDescription o) {
    if (o.shape.dimensions[1] >= kShortestLeg) shapes.push_back(std::move(o));
  };
  const std::vector<kinematics::DhRow>& rows = chain.rows();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string name = robot + ".joint" + std::to_string(i + 1);
    // Joint i + 1 turns (or slides) about z of DH frame i (link i): its housing sits on that axis.
    planning::ObjectDescription joint = leg(robot, name, i, KDL::Vector(0, 0, -housing), KDL::Vector(0, 0, housing), housing);
    joint.group = robot + ".joints";
    add(std::move(joint));
    // Frame i's origin, the elbow after d along z_i and frame i + 1's origin, in frame i + 1: for
    // a revolute joint they do not depend on q (Rz(θ + q) comes first in the DH transform).
    const KDL::Frame inverse = kinematics::dhTransform(rows[i], 0.0).Inverse();
    const KDL::Vector start = inverse * KDL::Vector::Zero(), elbow = inverse * KDL::Vector(0, 0, rows[i].d);
    if (rows[i].type == kinematics::JointType::Revolute) add(leg(robot, name + ".d", i + 1, start, elbow, radius));
    add(leg(robot, name + ".a", i + 1, elbow, KDL::Vector::Zero(), radius));
  }
  // The flange to the tool (the chain's tool frame), in the last DH frame.
  add(leg(robot, robot + ".tool", rows.size(), KDL::Vector::Zero(), chain.tool().p, 0.5 * radius));
  return shapes;
}

}  // namespace cobra::studio
