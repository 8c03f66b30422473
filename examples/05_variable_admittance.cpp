// Example 05: the tank-based variable admittance library (cobra::control, thesis §4.5.3) on its own,
// without components: a point following a line while an analytic bump is in the way.
//
// The reference moves along x at constant height (a TGL quintic, 0.3 m in 3 s); a bump rises
// across its path, pushing back with a spring of 20,000 N/m. The admittance yields to the contact
// force and slides up the surface. Past the top the program lowers the stiffness with
// setParameters, to show what the energy tank is for: a stiffness that changes while the spring is
// loaded could give energy back to the environment, and the tank only lets that happen within the
// energy it stored from the damping. The program writes nominal and actual path, contact force and
// tank energy to an SVG file (first argument, default /tmp/cobra-variable-admittance.svg) and
// checks that there was contact and that the tank never went below ε.
//
// This is the library, not the thesis' experiment: Fig. 6.7 (the Puma 260 following a line across
// an unexpected surface with one configuration throughout, §6.3-6.4) is drawn from a run of the
// application apps/puma260 (`./do demo puma260`).

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cobra/control/variable_admittance.hpp"
#include "cobra/plot/svg_plot.hpp"
#include "cobra/trajectory/polynomial.hpp"

using namespace cobra;

namespace {

control::Matrix6 diagonal(double x, double y, double z, double rotation) {
  control::Vector6 d;
  d << x, y, z, rotation, rotation, rotation;
  return d.asDiagonal();
}

/// Height of the obstacle's surface under x (m): a bump 2 cm high around x = 0.15 m.
double surface(double x) { return 0.02 * std::exp(-std::pow((x - 0.15) / 0.04, 2)); }

}  // namespace

int main(int argc, char** argv) {
  const char* output = argc > 1 ? argv[1] : "/tmp/cobra-variable-admittance.svg";
  control::AdmittanceParameters p;
  p.constant_inertia = diagonal(1, 1, 1, 0.05);
  p.constant_stiffness = diagonal(200, 200, 200, 5);
  p.inertia = diagonal(3, 3, 3, 0.1);
  p.stiffness = diagonal(2000, 2000, 2000, 40);
  p.damping = diagonal(150, 150, 150, 4);
  p.tank = {3.0, 10.0, 0.5};
  control::VariableAdmittance admittance(p);

  const trajectory::Polynomial line(5, trajectory::Conditions(trajectory::State{0.0}, trajectory::State{0.3}), 3.0);
  const double dt = 1e-3, environment_stiffness = 20000.0;  // s, N/m
  plot::Figure figure{"Tank-based variable admittance on a point against an analytic bump (library example)", {}};
  figure.panels = {{"path in the x-z plane", "x [m]", "z [m]", {{"nominal", {}, {}, true}, {"actual", {}, {}}, {"surface", {}, {}, true}}},
                   {"contact force", "t [s]", "F_z [N]", {{"F_z", {}, {}}}},
                   {"energy tank", "t [s]", "T [J]", {{"tank", {}, {}}, {"ε", {}, {}, true}}}};
  KDL::Frame pose = KDL::Frame::Identity();
  KDL::Twist twist;
  bool softened = false;
  double lowest = 1e9, highest_contact = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    const double t = i * dt;
    trajectory::State s;
    line.evaluate(std::min(t, 3.0), s);
    const KDL::Frame reference(KDL::Vector(s.position, 0.0, 0.0));
    const KDL::Twist reference_twist(KDL::Vector(t < 3.0 ? s.velocity : 0.0, 0, 0), KDL::Vector::Zero());
    const double depth = surface(pose.p.x()) - pose.p.z();  // > 0: the tool is inside the obstacle
    const double fz = depth > 0.0 ? environment_stiffness * depth : 0.0;
    if (!softened && pose.p.x() > 0.15) {  // past the top: lower stiffness, which the tank guards
      admittance.setParameters(diagonal(3, 3, 3, 0.1), diagonal(150, 150, 150, 4), diagonal(800, 800, 400, 20));
      softened = true;
    }
    admittance.step(reference, reference_twist, KDL::Wrench(KDL::Vector(0, 0, fz), KDL::Vector::Zero()), dt, pose, twist);
    lowest = std::min(lowest, admittance.tankEnergy());
    highest_contact = std::max(highest_contact, fz);
    if (i % 10 != 0) continue;
    figure.panels[0].series[0].x.push_back(reference.p.x());
    figure.panels[0].series[0].y.push_back(reference.p.z());
    figure.panels[0].series[1].x.push_back(pose.p.x());
    figure.panels[0].series[1].y.push_back(pose.p.z());
    figure.panels[0].series[2].x.push_back(pose.p.x());
    figure.panels[0].series[2].y.push_back(surface(pose.p.x()));
    figure.panels[1].series[0].x.push_back(t);
    figure.panels[1].series[0].y.push_back(fz);
    figure.panels[2].series[0].x.push_back(t);
    figure.panels[2].series[0].y.push_back(admittance.tankEnergy());
    figure.panels[2].series[1].x.push_back(t);
    figure.panels[2].series[1].y.push_back(p.tank.min_energy);
  }
  plot::writeSvg(figure, output);
  std::printf("largest contact force %.2f N; tank between %.3f J and its start %.1f J (ε = %.1f J)\n", highest_contact,
              lowest, p.tank.initial_energy, p.tank.min_energy);
  std::printf("wrote %s\n", output);
  return lowest >= p.tank.min_energy && highest_contact > 1.0 ? 0 : 1;
}
