#pragma once
// What cobra studio draws beside the robots (run.studio.extras, studio/README.md "Extras"), for the
// Robot Visualizer Bridge: the extras that move are read from ports into the snapshot each frame
// (sphere, plane, points, polyline, segments); the fixed ones (spheres, capsules, cylinders,
// slabs) are read once at setup from components' properties and go into the model (sent once).
// Everything is in the world frame, m.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "cobra/planning/scene.hpp"
#include "cobra/run/run_spec.hpp"
#include "cobra/run/runner.hpp"

namespace cobra::studio {

class Extras {
 public:
  Extras();
  ~Extras();
  Extras(const Extras&) = delete;
  Extras& operator=(const Extras&) = delete;

  // Connects to the ports and reads the properties run.studio.extras names; the moving extras'
  // numbers go at values[offset ...] of each snapshot. `scene`: the drawn planning scene (a
  // slab's footprint may name one of its boxes), nullptr when the app draws none.
  // @throws std::runtime_error "FILE:LINE: run.studio.extras.NAME: ..." naming the component,
  //         port or property and what was expected.
  void attach(const run::RunContext& run, const planning::SceneDescription* scene, std::size_t offset);
  // Numbers of a snapshot the moving extras take.
  std::size_t width() const { return width_; }
  // The model's extras entries, comma-separated: {"name","kind","frame", ...}.
  void appendModel(std::string& out) const;
  // Reads the ports into values (the snapshot's numbers). Real time: allocates nothing, throws nothing.
  void fill(double* values);
  // The members of a frame's "extras" object (the moving extras only).
  void appendFrame(std::string& out, const double* values) const;

  struct View;

 private:
  std::vector<std::unique_ptr<View>> views_;
  std::size_t width_ = 0;
};

}  // namespace cobra::studio
