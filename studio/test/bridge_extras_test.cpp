// What the Robot Visualizer Bridge draws beside the robots (studio/src/extras.cpp) on the real
// applications: the puncturing phantom's tumour, forbidden regions and tissue layers are the
// components' own numbers (read once, in the model) and the scenario files' numbers; the suturing
// wound's edges, thread and stitches in a frame are the ports' values at that frame; the Puma 260's
// contact surface is its MuJoCo world's cylinder; a wrong fixed
// shape is one line naming the app file:line, the property and what was expected.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>

#include "cobra/run/port_tap.hpp"
#include "cobra/run/runner.hpp"
#include "cobra/studio/bridge.hpp"
#include "cobra/test_support/test_support.hpp"
#include "json_numbers.hpp"

namespace cobra::studio {
namespace {

const std::string kSource = COBRA_SOURCE_DIR;
const std::string kApps = kSource + "/studio/test/apps/";

// Forwards to the bridge; at attach reads the named vector<double> properties, and at each frame
// the bridge publishes the named vector<double> ports (the values that frame must hold).
class Probe final : public run::RunObserver {
 public:
  Probe(VisualizerBridge& bridge, std::vector<std::string> property_names, std::vector<std::string> port_names)
      : bridge_(bridge), property_names_(std::move(property_names)), port_names_(std::move(port_names)) {}
  void attach(const run::RunContext& run) override {
    bridge_.attach(run);
    for (const std::string& path : property_names_) {
      const auto dot = path.find('.');
      properties[path] = run.registry.find(path.substr(0, dot))->getProperty<std::vector<double>>(path.substr(dot + 1));
    }
    for (const std::string& path : port_names_)
      taps_.push_back(std::make_unique<run::Tap<std::vector<double>>>(run.registry, path, "test", "probe", "vector<double>"));
  }
  void step(const run::StepView& now) override {
    const long before = bridge_.stats().published;
    bridge_.step(now);
    if (bridge_.stats().published == before) return;
    for (std::size_t i = 0; i < taps_.size(); ++i) taps_[i]->read(ports[port_names_[i]]);
  }
  void event(double t, const std::string& source, const std::string& name) override { bridge_.event(t, source, name); }
  bool nextInput(std::size_t& index) override { return bridge_.nextInput(index); }
  std::vector<std::string> finished(const run::RunResult& result) override { return bridge_.finished(result); }

  std::map<std::string, std::vector<double>> properties, ports;

 private:
  VisualizerBridge& bridge_;
  std::vector<std::string> property_names_, port_names_;
  std::vector<std::unique_ptr<run::Tap<std::vector<double>>>> taps_;
};

// The model's (or frame's) entry of extra `name`: the text from its name to its end.
std::string entryOf(const std::string& json, const std::string& start) {
  const auto at = json.find(start);
  if (at == std::string::npos) return {};
  return json.substr(at, json.find('}', at) - at + 1);
}

void expectNear(const std::vector<double>& got, const std::vector<double>& want, double tolerance, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], tolerance) << what << " [" << i << "]";
}

TEST(VisualizerBridgeExtras, PuncturingTumourForbiddenRegionsAndLayersAreTheComponentsAndTheFilesNumbers) {
  VisualizerBridge bridge;
  Probe probe(bridge, {"Patient.tumour", "NeedleMonitor.forbidden_regions", "Patient.layer_depths"}, {});
  run::RunOptions options;
  options.app = kSource + "/apps/puncturing";
  options.time_limit = 0.1;  // s: the shapes are read at setup
  options.observer = &probe;
  run::runApp(options);
  int status = 0;
  const std::string model = bridge.model(status);
  ASSERT_EQ(status, 200) << model;

  // The JSON's 9 significant digits: 1e-9 m on numbers below 1 m.
  const std::string tumour = entryOf(model, "{\"name\":\"tumour\",\"kind\":\"spheres\",\"frame\":\"world\",\"shapes\":[[");
  ASSERT_FALSE(tumour.empty()) << model;
  expectNear(numbersAfter(tumour, "shapes"), probe.properties["Patient.tumour"], 1e-9, "tumour = Patient.tumour");
  // scenarios/two_needles/phantom.txt: centre (0, 0, -0.06) m, radius 12 mm, in the phantom placed
  // at the abdomen pose of preoperative.txt, (0, 0, 0.1) m.
  expectNear(numbersAfter(tumour, "shapes"), {0.0, 0.0, 0.04, 0.012}, 1e-9, "tumour = phantom.txt");

  const std::string forbidden = entryOf(model, "{\"name\":\"forbidden\",\"kind\":\"capsules\",\"frame\":\"world\",\"shapes\":[[");
  ASSERT_FALSE(forbidden.empty()) << model;
  expectNear(numbersAfter(forbidden, "shapes"), probe.properties["NeedleMonitor.forbidden_regions"], 1e-9,
             "forbidden = NeedleMonitor.forbidden_regions");
  // preoperative.txt: the rib capsule and the vessel sphere (a capsule of equal ends), frame A.
  expectNear(numbersAfter(forbidden, "shapes"),
             {-0.06, 0.03, 0.08, 0.06, 0.03, 0.08, 0.006, 0.02, -0.02, 0.03, 0.02, -0.02, 0.03, 0.004}, 1e-9,
             "forbidden = preoperative.txt");

  const std::string layers = entryOf(model, "{\"name\":\"layers\",\"kind\":\"boxes\",\"frame\":\"world\",\"shapes\":[[");
  ASSERT_FALSE(layers.empty()) << model;
  const std::vector<double> boxes = numbersAfter(layers, "shapes");
  const std::vector<double>& depths = probe.properties["Patient.layer_depths"];
  // phantom.txt: skin 2 mm, fat 15 mm, muscle 15 mm, kidney 60 mm below the skin at z = 0.1 m,
  // each across the scene's phantom box (apps/puncturing/deployment/puncturing.scene: 0.3 x 0.22 m).
  expectNear(depths, {0.0, 0.002, 0.002, 0.017, 0.017, 0.032, 0.032, 0.092}, 1e-12, "Patient.layer_depths");
  ASSERT_EQ(boxes.size(), 4u * 10u);
  for (std::size_t i = 0; i < 4; ++i) {
    const double top = depths[2 * i], bottom = depths[2 * i + 1];
    expectNear(std::vector<double>(boxes.begin() + 10 * i, boxes.begin() + 10 * (i + 1)),
               {0.0, 0.0, 0.1 - 0.5 * (top + bottom), 0.0, 0.0, 0.0, 1.0, 0.3, 0.22, bottom - top}, 1e-9,
               "layer " + std::to_string(i));
  }

  std::uint64_t seq = 0;
  std::string frame;
  ASSERT_TRUE(bridge.latestFrame(seq, frame));
  EXPECT_EQ(frame.find("\"tumour\""), std::string::npos) << "fixed shapes are in the model only: " << frame;
  EXPECT_NE(frame.find("\"needle_measured\":{\"points\":[["), std::string::npos) << frame;
}

TEST(VisualizerBridgeExtras, SuturingEdgesThreadAndStitchesInAFrameAreThePortsValuesAtThatFrame) {
  VisualizerBridge bridge;
  Probe probe(bridge, {}, {"Patient.woundEdges", "Patient.threadPath", "Patient.stitchLines"});
  run::RunOptions options;
  options.app = kSource + "/apps/suturing";
  options.time_limit = 20.0;  // s: both halves of the first stitch applied (at 6.7 and 14.7 s)
  options.observer = &probe;
  run::runApp(options);
  int status = 0;
  const std::string model = bridge.model(status);
  EXPECT_NE(model.find("{\"name\":\"thread\",\"kind\":\"polyline\",\"frame\":\"world\",\"strands\":1}"), std::string::npos) << model;
  EXPECT_NE(model.find("{\"name\":\"stitches\",\"kind\":\"segments\",\"frame\":\"world\"}"), std::string::npos) << model;
  std::uint64_t seq = 0;
  std::string frame;
  ASSERT_TRUE(bridge.latestFrame(seq, frame));
  const std::vector<double> thread = probe.ports["Patient.threadPath"], stitches = probe.ports["Patient.stitchLines"];
  EXPECT_GE(thread.size(), 3u * 3u) << "two skin points and the tip";
  EXPECT_EQ(stitches.size(), 3u * 6u) << "one complete stitch: two halves and the crossing";
  expectNear(numbersAfter(frame, "points", frame.find("\"thread\":{")), thread, 1e-9, "thread");
  expectNear(numbersAfter(frame, "points", frame.find("\"stitches\":{")), stitches, 1e-9, "stitches");
  expectNear(numbersAfter(frame, "points", frame.find("\"wound_edges\":{")), probe.ports["Patient.woundEdges"], 1e-9,
             "wound_edges");
}

TEST(VisualizerBridgeExtras, ThePuma260ContactSurfaceIsTheWorldsCylinderAndTheAnalyticWorldHasNone) {
  VisualizerBridge bridge;
  Probe probe(bridge, {"World.surface_cylinder"}, {});
  run::RunOptions options;
  options.app = kSource + "/apps/puma260";
  options.time_limit = 0.1;  // s
  options.observer = &probe;
  run::runApp(options);
  int status = 0;
  const std::string model = bridge.model(status);
  const std::string surface = entryOf(model, "{\"name\":\"surface\",\"kind\":\"cylinders\",\"frame\":\"world\",\"shapes\":[[");
  ASSERT_FALSE(surface.empty()) << model;
  expectNear(numbersAfter(surface, "shapes"), probe.properties["World.surface_cylinder"], 1e-9, "surface = World.surface_cylinder");
  // apps/puma260/world/puma260.xml: radius 0.08 m, 0.1 m long along the base x axis at (0.35, 0, 0.035) m.
  expectNear(numbersAfter(surface, "shapes"), {0.30, 0.0, 0.035, 0.40, 0.0, 0.035, 0.08}, 1e-9, "surface = puma260.xml");

  VisualizerBridge analytic;
  options.scenario = kSource + "/apps/puma260/scenarios/no_contact";
  options.observer = &analytic;
  run::runApp(options);
  const std::string without = analytic.model(status);
  ASSERT_EQ(status, 200) << without;
  EXPECT_EQ(without.find("\"surface\""), std::string::npos) << "the analytic world has no surface: " << without;
}

std::string shapeError(const std::string& which) {
  VisualizerBridge bridge;
  run::RunOptions options;
  options.app = kApps + "bad_shapes.lua";
  options.before_lua = "shape_case = '" + which + "'";
  options.observer = &bridge;
  return test_support::messageOf([&] { run::runApp(options); });
}

TEST(VisualizerBridgeExtras, AWrongFixedShapeNamesTheAppFileLineThePropertyAndWhatIsExpected) {
  const std::string file = kApps + "bad_shapes.lua";
  EXPECT_EQ(shapeError("unknown"), file + ":6: run.studio.extras.tumour_a: component 'Patient' has no property 'tumor'; "
                                          "did you mean 'tumour'? known properties: scenario_file, phantom_pose, tip_to_needle, "
                                          "iceball_max_radius, freeze_time_constant, thaw_time_constant, release_radius, hold_stiffness, "
                                          "freeze_duration, probe_contact_stiffness, probe_min_contact_force, plane_tolerance, "
                                          "image_depth, image_half_width, needle_visible_length, image_rate, image_seed, "
                                          "image_width, image_height, image_spacing, image_pixels_per_step, tumour, layer_depths");
  EXPECT_EQ(shapeError("type"), file + ":7: run.studio.extras.tumour_b: property Patient.iceball_max_radius is a double; "
                                       "expected vector<double>, 4 per sphere (centre x y z, radius; m, world)");
  EXPECT_EQ(shapeError("count"), file + ":8: run.studio.extras.regions_c: property NeedleMonitor.forbidden_regions has 14 "
                                        "numbers; expected 4 per sphere (centre x y z, radius; m, world)");
  EXPECT_EQ(shapeError("box"), file + ":9: run.studio.extras.layers_d: the scene has no box 'phantm'; did you mean 'phantom'? "
                                      "known boxes: isur_frame, us_probe, table, phantom");
  EXPECT_EQ(shapeError("frame"), file + ":10: run.studio.extras.layers_e: property Patient.tumour is a vector<double>; "
                                        "expected KDL.Frame (the skin's pose, m)");
  EXPECT_EQ(shapeError("noscene"), file + ":11: run.studio.extras.layers_f: size = \"phantom\" names an object of "
                                          "run.studio.scene, and the table draws no scene; give size = { width, height } (m)");
}

}  // namespace
}  // namespace cobra::studio
