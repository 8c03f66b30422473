// Example 04: a synchronised multi-axis trajectory with TGL, drawn like the thesis' Fig. 3.5.
//
// Three axes go through five waypoints. MultiAxisTrajectory gives every segment the duration its
// slowest axis needs at its maximum velocity, slows the others down to it, and joins the linear
// segments with quintic (order 5) blends of duration T_a. The program writes position, velocity
// and acceleration of the three axes to an SVG file (first argument, default
// /tmp/cobra-fig-3-5.svg), with the waypoint crossing times marked, and checks what the
// figure shows: every axis at the same waypoint times, no axis above its velocity limit.

#include <cmath>
#include <cstdio>
#include <vector>

#include "cobra/plot/svg_plot.hpp"
#include "cobra/trajectory/multi_axis.hpp"

using namespace cobra;

int main(int argc, char** argv) {
  const char* output = argc > 1 ? argv[1] : "/tmp/cobra-fig-3-5.svg";

  // Waypoints (m) of three Cartesian axes, and per-axis limits.
  const trajectory::MultiAxisPath path({{0.00, 0.00, 0.10},
                                        {0.10, 0.05, 0.12},
                                        {0.15, 0.15, 0.08},
                                        {0.25, 0.12, 0.05},
                                        {0.30, 0.00, 0.10}});
  const trajectory::AxisLimits limits{{0.10, 0.08, 0.05}, {0.2, 0.2, 0.2}};  // m/s; T_a in s
  const trajectory::MultiAxisTrajectory motion(path, limits, 5);

  const std::size_t axes = motion.axisCount();
  const char* names[] = {"x", "y", "z"};
  plot::Figure figure{"Synchronised multi-point trajectory, quintic blends (cf. thesis Fig. 3.5)", {}};
  figure.panels = {{"position", "t [s]", "q [m]", {}},
                   {"velocity", "t [s]", "dq/dt [m/s]", {}},
                   {"acceleration", "t [s]", "d2q/dt2 [m/s2]", {}}};
  std::vector<trajectory::State> states(axes);
  for (std::size_t a = 0; a < axes; ++a)
    for (auto& panel : figure.panels) panel.series.push_back({names[a], {}, {}});
  const int samples = 600;
  double fastest[3] = {0, 0, 0};
  for (int i = 0; i <= samples; ++i) {
    const double t = motion.duration() * i / samples;
    motion.evaluate(t, states);
    for (std::size_t a = 0; a < axes; ++a) {
      const double values[] = {states[a].position, states[a].velocity, states[a].acceleration};
      for (std::size_t p = 0; p < 3; ++p) {
        figure.panels[p].series[a].x.push_back(t);
        figure.panels[p].series[a].y.push_back(values[p]);
      }
      fastest[a] = std::max(fastest[a], std::abs(states[a].velocity));
    }
  }
  // Waypoint markers: every axis at its waypoint at the same instants.
  for (std::size_t k = 0; k < path.size(); ++k)
    for (std::size_t a = 0; a < axes; ++a) {
      figure.panels[0].series[a].marker_x.push_back(motion.waypointTimes()[k]);
      figure.panels[0].series[a].marker_y.push_back(path.waypoint(k)[a]);
    }
  plot::writeSvg(figure, output);

  std::printf("duration %.3f s; waypoint times:", motion.duration());
  for (double t : motion.waypointTimes()) std::printf(" %.3f", t);
  std::printf("\n");
  bool ok = true;
  for (std::size_t a = 0; a < axes; ++a) {
    std::printf("axis %s: peak speed %.4f m/s (limit %.2f)\n", names[a], fastest[a], limits.max_velocity[a]);
    ok = ok && fastest[a] <= limits.max_velocity[a] * (1 + 1e-9);
  }
  motion.evaluate(motion.duration(), states);
  for (std::size_t a = 0; a < axes; ++a) ok = ok && std::abs(states[a].position - path.waypoint(path.size() - 1)[a]) < 1e-12;
  std::printf("wrote %s\n", output);
  return ok ? 0 : 1;
}
