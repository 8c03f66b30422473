// libFuzzer target: the phantom scenario text format of the simulated abdomen
// (cobra::sim::parseScenario, sim/include/cobra/sim/phantom.hpp). Checks that any text either
// parses into a scenario that passes validate() or is refused with std::invalid_argument whose
// message names the source and, when it names a line, a line of the text; that a parsed scenario,
// printed back into the format (every number with its shortest exact decimal form), parses to
// the same scenario; and that nothing crashes.

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cobra/sim/phantom.hpp"
#include "fuzz_support.hpp"

namespace {

using cobra::fuzz::exact;
using cobra::fuzz::exactVector;
using cobra::fuzz::identical;

std::string tissueKeys(const cobra::sim::TissueProperties& t) {
  return " puncture_force=" + exact(t.puncture_force) + " k1=" + exact(t.k1) + " k2=" + exact(t.k2) +
         " cutting_force=" + exact(t.cutting_force) + " coulomb_friction=" + exact(t.coulomb_friction) +
         " viscous_friction=" + exact(t.viscous_friction) + " lateral_stiffness=" + exact(t.lateral_stiffness);
}

/// The scenario in the text format (the library has no printer: the format is written by hand).
std::string print(const cobra::sim::PhantomScenario& s) {
  std::string out;
  for (const auto& layer : s.layers)
    out += "layer " + layer.tissue.name + " thickness=" + exact(layer.thickness) + tissueKeys(layer.tissue) + "\n";
  out += "tumour center=" + exactVector(s.tumour_center) + " radius=" + exact(s.tumour_radius) +
         tissueKeys(s.tumour_tissue) + "\n";
  for (const auto& r : s.forbidden)
    out += "capsule " + r.name + " a=" + exactVector(r.a) + " b=" + exactVector(r.b) + " radius=" + exact(r.radius) + "\n";
  out += "penalty_stiffness " + exact(s.penalty_stiffness) + "\n";
  return out;
}

bool same(const cobra::sim::TissueProperties& a, const cobra::sim::TissueProperties& b) {
  return a.name == b.name && a.puncture_force == b.puncture_force && a.k1 == b.k1 && a.k2 == b.k2 &&
         a.cutting_force == b.cutting_force && a.coulomb_friction == b.coulomb_friction &&
         a.viscous_friction == b.viscous_friction && a.lateral_stiffness == b.lateral_stiffness;
}

bool same(const cobra::sim::PhantomScenario& a, const cobra::sim::PhantomScenario& b) {
  if (a.layers.size() != b.layers.size() || a.forbidden.size() != b.forbidden.size()) return false;
  for (std::size_t i = 0; i < a.layers.size(); ++i)
    if (!same(a.layers[i].tissue, b.layers[i].tissue) || a.layers[i].thickness != b.layers[i].thickness) return false;
  for (std::size_t i = 0; i < a.forbidden.size(); ++i) {
    const auto &x = a.forbidden[i], &y = b.forbidden[i];
    if (x.name != y.name || !identical(x.a, y.a) || !identical(x.b, y.b) || x.radius != y.radius) return false;
  }
  return same(a.tumour_tissue, b.tumour_tissue) && identical(a.tumour_center, b.tumour_center) &&
         a.tumour_radius == b.tumour_radius && a.penalty_stiffness == b.penalty_stiffness;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  cobra::sim::PhantomScenario scenario;
  try {
    scenario = cobra::sim::parseScenario(text, "fuzz.phantom");
  } catch (const std::invalid_argument& e) {
    cobra::fuzz::requireLocated(e.what(), "fuzz.phantom", text);
    return 0;
  }
  try {
    cobra::sim::validate(scenario);  // what the parser accepts is a valid scenario
  } catch (const std::invalid_argument&) {
    std::abort();
  }
  const std::string printed = print(scenario);
  try {
    if (!same(cobra::sim::parseScenario(printed, "printed"), scenario)) std::abort();
  } catch (const std::invalid_argument&) {
    std::abort();  // the parser refuses the text of a scenario it accepted
  }
  return 0;
}
