#include "cobra/sim/phantom.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cobra::sim {
namespace {

TissueProperties tissue(std::string name, double puncture, double k1, double k2, double cutting, double coulomb,
                        double viscous, double lateral) {
  return {std::move(name), puncture, k1, k2, cutting, coulomb, viscous, lateral};
}

void checkNonNegative(const std::string& where, const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value < 0.0) {
    throw std::invalid_argument(where + ": " + parameter + " = " + std::to_string(value) + ", expected >= 0 " + unit);
  }
}
void checkPositive(const std::string& where, const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(where + ": " + parameter + " = " + std::to_string(value) + ", expected > 0 " + unit);
  }
}

void validateTissue(const std::string& where, const TissueProperties& t) {
  checkPositive(where, "puncture_force", t.puncture_force, "N");
  checkNonNegative(where, "k1", t.k1, "N/m");
  checkNonNegative(where, "k2", t.k2, "N/m^2");
  if (t.k1 == 0.0 && t.k2 == 0.0) throw std::invalid_argument(where + ": k1 and k2 are both 0; the membrane never ruptures");
  checkNonNegative(where, "cutting_force", t.cutting_force, "N");
  checkNonNegative(where, "coulomb_friction", t.coulomb_friction, "N/m");
  checkNonNegative(where, "viscous_friction", t.viscous_friction, "N*s/m^2");
  checkNonNegative(where, "lateral_stiffness", t.lateral_stiffness, "N/m");
}

// --- text format -------------------------------------------------------------------------------

struct LineContext {
  std::string where;  // "source:line"
  [[noreturn]] void fail(const std::string& message) const { throw std::invalid_argument(where + ": " + message); }
};

double parseNumber(const LineContext& ctx, std::string_view key, std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    ctx.fail("value of '" + std::string(key) + "' is '" + std::string(text) + "', expected a number");
  }
  return value;
}

KDL::Vector parseVector(const LineContext& ctx, std::string_view key, std::string_view text) {
  double xyz[3];
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = text.find(',');
    if ((i < 2) != (comma != std::string_view::npos)) {
      ctx.fail("value of '" + std::string(key) + "' must be X,Y,Z (m)");
    }
    xyz[i] = parseNumber(ctx, key, text.substr(0, comma));
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
  }
  return {xyz[0], xyz[1], xyz[2]};
}

bool setTissueKey(const LineContext& ctx, TissueProperties& t, std::string_view key, std::string_view value) {
  struct Entry {
    const char* key;
    double TissueProperties::*field;
  };
  static constexpr Entry kKeys[] = {
      {"puncture_force", &TissueProperties::puncture_force}, {"k1", &TissueProperties::k1},
      {"k2", &TissueProperties::k2},
      {"cutting_force", &TissueProperties::cutting_force},   {"coulomb_friction", &TissueProperties::coulomb_friction},
      {"viscous_friction", &TissueProperties::viscous_friction},
      {"lateral_stiffness", &TissueProperties::lateral_stiffness}};
  for (const Entry& e : kKeys) {
    if (key == e.key) {
      t.*e.field = parseNumber(ctx, key, value);
      return true;
    }
  }
  return false;
}

}  // namespace

// Sources. Skin puncture force 1.5 N: within the 1-2 N reported for skin by the needle-insertion
// review of Abolhassani, Patel and Moallem (Med. Eng. Phys. 29, 2007). Membrane model
// f = k1·x + k2·x² before puncture: the capsule-stiffness form of Okamura, Simone and O'Leary,
// "Force modeling for needle insertion into soft tissue" (IEEE TBME 51(10), 2004); their
// cutting-force and friction terms (constant cutting, Karnopp friction along the shaft) are the
// model of needle_tissue.cpp. Every NUMBER below other than the skin puncture force is an
// ASSUMPTION chosen to be of the order those papers report (forces < 3 N at clinical speeds),
// not a fit: thicknesses, stiffnesses, cutting forces, friction and lateral stiffness.
PhantomScenario defaultAbdomen() {
  PhantomScenario s;
  s.layers = {
      {tissue("skin", 1.5, 500.0, 3.0e5, 0.4, 8.0, 40.0, 800.0), 0.002},
      {tissue("fat", 0.4, 100.0, 2.0e4, 0.1, 2.0, 20.0, 200.0), 0.015},
      {tissue("muscle", 1.0, 250.0, 5.0e4, 0.3, 6.0, 40.0, 600.0), 0.015},
      {tissue("kidney", 0.8, 200.0, 4.0e4, 0.2, 4.0, 30.0, 400.0), 0.060},
  };
  s.tumour_tissue = tissue("tumour", 1.2, 300.0, 8.0e4, 0.5, 6.0, 40.0, 800.0);
  s.tumour_center = KDL::Vector(0.0, 0.0, -0.060);
  s.tumour_radius = 0.010;
  s.forbidden = {{"rib", KDL::Vector(-0.06, 0.03, -0.02), KDL::Vector(0.06, 0.03, -0.02), 0.006},
                 {"vessel", KDL::Vector(0.02, -0.02, -0.07), KDL::Vector(0.02, -0.02, -0.07), 0.004}};
  s.penalty_stiffness = 1.0e5;
  return s;
}

void validate(const PhantomScenario& s) {
  if (s.layers.empty()) throw std::invalid_argument("phantom: layers is empty, expected at least one (skin)");
  for (std::size_t i = 0; i < s.layers.size(); ++i) {
    const std::string where = "phantom layer " + std::to_string(i + 1) + " '" + s.layers[i].tissue.name + "'";
    checkPositive(where, "thickness", s.layers[i].thickness, "m");
    validateTissue(where, s.layers[i].tissue);
  }
  validateTissue("phantom tumour", s.tumour_tissue);
  checkPositive("phantom tumour", "radius", s.tumour_radius, "m");
  for (const ForbiddenRegion& r : s.forbidden) checkPositive("phantom forbidden region '" + r.name + "'", "radius", r.radius, "m");
  checkPositive("phantom", "penalty_stiffness", s.penalty_stiffness, "N/m");
}

double layerTop(const PhantomScenario& scenario, std::size_t layer) noexcept {
  double top = 0.0;
  for (std::size_t i = 0; i < layer && i < scenario.layers.size(); ++i) top += scenario.layers[i].thickness;
  return top;
}

PhantomScenario parseScenario(std::string_view text, std::string_view source) {
  PhantomScenario s = defaultAbdomen();
  s.layers.clear();
  s.forbidden.clear();
  bool tumour_seen = false;
  std::istringstream lines{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const LineContext ctx{std::string(source) + ":" + std::to_string(number)};
    if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string statement;
    if (!(words >> statement)) continue;
    std::vector<std::string> args;
    for (std::string w; words >> w;) args.push_back(w);
    auto needName = [&]() -> std::string {
      if (args.empty() || args[0].find('=') != std::string::npos) ctx.fail("'" + statement + "' needs a NAME first");
      std::string name = args[0];
      args.erase(args.begin());
      return name;
    };
    if (statement == "penalty_stiffness") {
      if (args.size() != 1) ctx.fail("penalty_stiffness takes one value (N/m)");
      s.penalty_stiffness = parseNumber(ctx, statement, args[0]);
      if (s.penalty_stiffness <= 0.0) ctx.fail("penalty_stiffness = " + args[0] + ", expected > 0 N/m");
      continue;
    }
    TissueLayer layer;
    ForbiddenRegion region;
    bool has_center = false, has_radius = false, has_a = false, has_b = false, has_thickness = false;
    if (statement == "layer") {
      layer.tissue.name = needName();
    } else if (statement == "sphere" || statement == "capsule") {
      region.name = needName();
    } else if (statement == "tumour") {
      if (tumour_seen) ctx.fail("a second tumour; the phantom has one");
      tumour_seen = true;
      s.tumour_tissue = TissueProperties{};
      s.tumour_tissue.name = "tumour";
    } else {
      ctx.fail("unknown statement '" + statement + "', expected layer, tumour, sphere, capsule or penalty_stiffness");
    }
    for (const std::string& arg : args) {
      const std::size_t eq = arg.find('=');
      if (eq == std::string::npos) ctx.fail("'" + arg + "' is not KEY=VALUE");
      const std::string_view key = std::string_view(arg).substr(0, eq);
      const std::string_view value = std::string_view(arg).substr(eq + 1);
      if (statement == "layer" && key == "thickness") {
        layer.thickness = parseNumber(ctx, key, value);
        has_thickness = true;
      } else if (statement == "layer" && setTissueKey(ctx, layer.tissue, key, value)) {
      } else if (statement == "tumour" && key == "center") {
        s.tumour_center = parseVector(ctx, key, value);
        has_center = true;
      } else if (statement == "tumour" && key == "radius") {
        s.tumour_radius = parseNumber(ctx, key, value);
        has_radius = true;
      } else if (statement == "tumour" && setTissueKey(ctx, s.tumour_tissue, key, value)) {
      } else if (statement == "sphere" && key == "center") {
        region.a = region.b = parseVector(ctx, key, value);
        has_a = has_b = true;
      } else if (statement == "capsule" && (key == "a" || key == "b")) {
        (key == "a" ? region.a : region.b) = parseVector(ctx, key, value);
        (key == "a" ? has_a : has_b) = true;
      } else if ((statement == "sphere" || statement == "capsule") && key == "radius") {
        region.radius = parseNumber(ctx, key, value);
        has_radius = true;
      } else {
        ctx.fail("unknown key '" + std::string(key) + "' for '" + statement + "'");
      }
    }
    try {
      if (statement == "layer") {
        if (!has_thickness) ctx.fail("layer '" + layer.tissue.name + "' needs thickness=M");
        checkPositive("layer '" + layer.tissue.name + "'", "thickness", layer.thickness, "m");
        validateTissue("layer '" + layer.tissue.name + "'", layer.tissue);
        s.layers.push_back(layer);
      } else if (statement == "tumour") {
        if (!has_center || !has_radius) ctx.fail("tumour needs center=X,Y,Z and radius=M");
        validateTissue("tumour", s.tumour_tissue);
        checkPositive("tumour", "radius", s.tumour_radius, "m");
      } else {
        if (!has_a || !has_b || !has_radius) {
          ctx.fail(statement == "sphere" ? "sphere needs center=X,Y,Z and radius=M" : "capsule needs a=, b= and radius=");
        }
        checkPositive(statement + " '" + region.name + "'", "radius", region.radius, "m");
        s.forbidden.push_back(region);
      }
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      if (message.rfind(ctx.where, 0) == 0) throw;
      ctx.fail(message);
    }
  }
  if (s.layers.empty()) throw std::invalid_argument(std::string(source) + ": no layer; the phantom needs at least one (skin)");
  if (!tumour_seen) throw std::invalid_argument(std::string(source) + ": no tumour statement");
  validate(s);
  return s;
}

PhantomScenario loadScenario(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::invalid_argument("phantom scenario '" + path + "' cannot be read");
  std::stringstream text;
  text << file.rdbuf();
  return parseScenario(text.str(), path);
}

}  // namespace cobra::sim
