#include "extras.hpp"
#include "read_property.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <kdl/frames.hpp>

#include "cobra/run/port_tap.hpp"
#include "cobra/studio/json.hpp"

namespace cobra::studio {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void appendNumbers(std::string& out, const double* values, std::size_t n) {
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    json::appendNumber(out, values[i]);
  }
  out += ']';
}

// Numbers per shape of a fixed kind, and what they are (for messages).
struct FixedKind {
  const char* kind;
  std::size_t per;
  const char* what;
};
constexpr FixedKind kFixed[] = {
    {"spheres", 4, "4 per sphere (centre x y z, radius; m, world)"},
    {"capsules", 7, "7 per capsule (x y z of both axis ends, radius; m, world)"},
    {"cylinders", 7, "7 per cylinder (x y z of both axis ends, radius; m, world)"},
    {"slabs", 2, "2 per slab (top and bottom depth below the pose's x-y plane; m)"},
};

}  // namespace

struct Extras::View {
  run::StudioSpec::Extra spec;
  // Moving extras.
  std::unique_ptr<run::Tap<KDL::Frame>> pose;
  std::unique_ptr<run::Tap<std::vector<double>>> list;  // points of a vector<double> port
  std::vector<double> sample;                          // its last value (capacity reserved)
  std::unique_ptr<run::Tap<double>> radius;
  std::size_t points = 1;  // points, polyline, segments: at most this many
  std::size_t offset = 0;  // sphere: centre (3), radius; plane: pose (7); points: count, then 3 each
  // Fixed extras: the wire kind and each shape's numbers (spheres: x y z r; capsules, cylinders:
  // a, b, r; boxes: pose (7), full lengths (3)).
  std::string wire_kind;
  std::vector<std::vector<double>> shapes;

  bool moving() const { return shapes.empty() && wire_kind.empty(); }
};

Extras::Extras() = default;
Extras::~Extras() = default;

namespace {

void attachMoving(Extras::View& view, const run::RunContext& run, const std::string& at, const std::string& use) {
  const run::StudioSpec::Extra& e = view.spec;
  const bool lines = e.kind == "points" || e.kind == "polyline" || e.kind == "segments";
  const bool frame = !lines || (e.kind == "points" && run::findOutput(run.registry, e.pose, at, use).type().name == "KDL.Frame");
  if (frame) {
    view.pose = std::make_unique<run::Tap<KDL::Frame>>(run.registry, e.pose, at, use, "KDL.Frame");
  } else {
    view.list = std::make_unique<run::Tap<std::vector<double>>>(
        run.registry, e.pose, at, use,
        e.kind == "points" ? "KDL.Frame or vector<double> (x y z triples, m)" : "vector<double> (x y z triples, m)");
    view.points = static_cast<std::size_t>(e.max);
    view.sample.reserve(3 * view.points);
  }
  if (e.kind == "sphere") view.radius = std::make_unique<run::Tap<double>>(run.registry, e.radius, at, use, "double (m)");
}

// The footprint (width, height) of slabs: the numbers, or the x and y lengths of a box of the scene.
std::pair<double, double> footprint(const run::StudioSpec::Extra& e, const planning::SceneDescription* scene,
                                    const std::string& at, const std::string& use) {
  if (e.footprint.empty()) return {e.width, e.height};
  if (scene == nullptr)
    throw std::runtime_error(at + ": " + use + ": size = \"" + e.footprint +
                             "\" names an object of run.studio.scene, and the table draws no scene; give size = { width, height } (m)");
  std::vector<std::string> boxes;
  for (const planning::ObjectDescription& o : scene->objects) {
    if (o.shape.kind != planning::ShapeKind::Box) continue;
    if (o.name == e.footprint) return {o.shape.dimensions[0], o.shape.dimensions[1]};
    boxes.push_back(o.name);
  }
  throw std::runtime_error(at + ": " + use + ": the scene has no box '" + e.footprint + "'" +
                           deploy::suggestionText(e.footprint, boxes, "boxes"));
}

void attachFixed(Extras::View& view, const run::RunContext& run, const planning::SceneDescription* scene,
                 const std::string& at, const std::string& use) {
  const run::StudioSpec::Extra& e = view.spec;
  const FixedKind& kind = *std::find_if(std::begin(kFixed), std::end(kFixed), [&](const FixedKind& k) { return e.kind == k.kind; });
  const std::vector<double> values =
      readProperty<std::vector<double>>(run.registry, e.pose, at, use, std::string("vector<double>, ") + kind.what);
  if (values.size() % kind.per != 0)
    throw std::runtime_error(at + ": " + use + ": property " + e.pose + " has " + std::to_string(values.size()) +
                             " numbers; expected " + kind.what);
  for (std::size_t i = 0; i < values.size(); i += kind.per) {
    const std::vector<double> shape(values.begin() + static_cast<std::ptrdiff_t>(i),
                                    values.begin() + static_cast<std::ptrdiff_t>(i + kind.per));
    const std::string which = e.pose + " " + kind.kind + "[" + std::to_string(i / kind.per) + "]";
    if (!std::all_of(shape.begin(), shape.end(), [](double v) { return std::isfinite(v); }))
      throw std::runtime_error(at + ": " + use + ": " + which + " is not finite");
    if (e.kind != "slabs" && !(shape.back() > 0.0))
      throw std::runtime_error(at + ": " + use + ": " + which + " has radius " + std::to_string(shape.back()) + " m; expected > 0");
    if (e.kind == "slabs" && !(shape[1] > shape[0]))
      throw std::runtime_error(at + ": " + use + ": " + which + " goes from depth " + std::to_string(shape[0]) + " to " +
                               std::to_string(shape[1]) + " m; expected bottom > top");
    view.shapes.push_back(shape);
  }
  view.wire_kind = e.kind;
  if (e.kind != "slabs") return;
  // Each slab a box in the world: centred at mid-depth below the skin's pose, turned with it.
  view.wire_kind = "boxes";
  const auto frame = readProperty<KDL::Frame>(run.registry, e.frame, at, use, "KDL.Frame (the skin's pose, m)");
  const auto [width, height] = footprint(e, scene, at, use);
  for (std::vector<double>& slab : view.shapes) {
    const KDL::Frame centre = frame * KDL::Frame(KDL::Vector(0.0, 0.0, -0.5 * (slab[0] + slab[1])));
    std::vector<double> box(10);
    box[0] = centre.p.x(), box[1] = centre.p.y(), box[2] = centre.p.z();
    centre.M.GetQuaternion(box[3], box[4], box[5], box[6]);
    box[7] = width, box[8] = height, box[9] = slab[1] - slab[0];
    slab = std::move(box);
  }
}

}  // namespace

void Extras::attach(const run::RunContext& run, const planning::SceneDescription* scene, std::size_t offset) {
  width_ = 0;
  for (const run::StudioSpec::Extra& e : run.spec.studio.extras) {
    const std::string at = e.where.text(), use = "run.studio.extras." + e.name;
    auto view = std::make_unique<View>();
    view->spec = e;
    const bool fixed = std::any_of(std::begin(kFixed), std::end(kFixed), [&](const FixedKind& k) { return e.kind == k.kind; });
    if (fixed) {
      attachFixed(*view, run, scene, at, use);
    } else {
      attachMoving(*view, run, at, use);
      view->offset = offset + width_;
      width_ += e.kind == "plane" ? 7 : (e.kind == "sphere" ? 4 : 1 + 3 * view->points);
    }
    views_.push_back(std::move(view));
  }
}

void Extras::appendModel(std::string& out) const {
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const View& v = *views_[i];
    const run::StudioSpec::Extra& e = v.spec;
    const std::string kind = v.moving() ? e.kind : v.wire_kind;
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(e.name) + ",\"kind\":\"" + kind + "\",\"frame\":\"world\"";
    if (e.kind == "plane") {
      const double size[2] = {e.width, e.height};
      out += ",\"size\":";
      appendNumbers(out, size, 2);
    }
    if (e.kind == "polyline") out += ",\"strands\":" + std::to_string(e.strands);
    if (!v.moving()) {
      out += ",\"shapes\":[";
      for (std::size_t s = 0; s < v.shapes.size(); ++s) {
        if (s) out += ',';
        appendNumbers(out, v.shapes[s].data(), v.shapes[s].size());
      }
      out += ']';
    }
    out += '}';
  }
}

void Extras::fill(double* values) {
  for (const std::unique_ptr<View>& view : views_) {
    View& e = *view;
    if (!e.moving()) continue;
    double* out = values + e.offset;
    if (e.list) {  // x y z triples, as many as fit
      const std::size_t n = e.list->read(e.sample) ? std::min(e.points, e.sample.size() / 3) : 0;
      out[0] = static_cast<double>(n);
      std::copy(e.sample.begin(), e.sample.begin() + static_cast<std::ptrdiff_t>(3 * n), out + 1);
      continue;
    }
    KDL::Frame pose;
    const bool have = e.pose->read(pose);
    if (e.spec.kind == "points") {
      out[0] = have ? 1.0 : 0.0;
      out += 1;
    }
    if (e.spec.kind == "plane") {
      if (have) {
        out[0] = pose.p.x(), out[1] = pose.p.y(), out[2] = pose.p.z();
        pose.M.GetQuaternion(out[3], out[4], out[5], out[6]);
      } else {
        std::fill(out, out + 7, kNaN);
      }
      continue;
    }
    out[0] = have ? pose.p.x() : kNaN, out[1] = have ? pose.p.y() : kNaN, out[2] = have ? pose.p.z() : kNaN;
    if (e.radius) {
      double radius = kNaN;
      out[3] = e.radius->read(radius) ? radius : kNaN;
    }
  }
}

void Extras::appendFrame(std::string& out, const double* values) const {
  bool first = true;
  for (const std::unique_ptr<View>& view : views_) {
    const View& e = *view;
    if (!e.moving()) continue;
    const double* x = values + e.offset;
    out += std::string(first ? "" : ",") + json::quoted(e.spec.name) + ":{";
    first = false;
    if (e.spec.kind == "plane") {
      out += "\"pose\":";
      appendNumbers(out, x, 7);
    } else if (e.spec.kind == "sphere") {
      out += "\"center\":";
      appendNumbers(out, x, 3);
      out += ",\"radius\":";
      json::appendNumber(out, x[3]);
    } else {
      out += "\"points\":[";
      for (std::size_t p = 0; p < static_cast<std::size_t>(x[0]); ++p) {
        if (p) out += ',';
        appendNumbers(out, x + 1 + 3 * p, 3);
      }
      out += ']';
    }
    out += '}';
  }
}

}  // namespace cobra::studio
