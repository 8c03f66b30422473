// Speed of the simulated world (cobra::sim) on the lockstep clock's terms: simulated seconds per
// wall-clock second for a puncturing-like world stepped at 1 kHz, and the F/T sensor model
// against the same model written naively, side by side in the same run.
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max"). Groups:
//  - PuncturingWorld: two UR5s on ServoRobot + CartesianServo (closed-form IK every step), the
//    needle robot inserting and withdrawing a needle into the default abdomen phantom
//    (NeedleTissueModel), the probe robot holding the ultrasound probe (observe), an AtiNano17
//    behind the needle and an AtiNano43 behind the probe. One iteration = 1000 steps = 1 s of
//    simulated time; `realtime_factor` = simulated s per wall s. Target: >= 50.
//  - ComponentWorld: the same set-up as the components a puncturing deployment runs (package
//    cobra_sim): SimulatedISURRobot inserting and withdrawing the needle (IK every step),
//    SimulatedUR5Robot holding the probe (IK every step), PatientSimulator, NeedleInsertionMonitor,
//    UltrasoundMonitor and SimulatedOmniPhantom, wired by ports and stepped by the LockstepClock at
//    1 kHz. Same counters; the PuncturingWorld group above is its library-level peer. The patient
//    renders its ultrasound image only while usImage is read: `us_image_read` is the same world
//    with a reader on it (10 images per s, the default, in bands), the other renders none.
//  - UltrasoundImage: one B-mode-like image of the default abdomen (UltrasoundImager::render) with
//    the probe 45 mm beyond a needle's tip, beam on the tumour, the needle in plane; 128 x 128 and
//    256 x 256 pixels. The time column is per image (target for 128 x 128: a few ms).
//  - PatientUpdate: one update of the PatientSimulator alone at 1 kHz (the ComponentWorld's probe
//    and needle poses, usImage connected), by what the update does with the image: nothing
//    (image_rate 0), one band of 1024 px (the default image_pixels_per_step; image_rate 62.5 Hz makes
//    every update render a band of a 128 x 128 image, and every 16th publish it), the whole
//    128 x 128 image in one update (image_pixels_per_step 0, image_rate 1000 Hz: the peer, what an
//    unbanded image costs the update it falls in). The time column is per update; `worst_step_us`
//    is the longest single update's thread CPU time (us; each timed with CLOCK_THREAD_CPUTIME_ID,
//    whose two calls the time column includes). Target for a band: <= 0.2 ms, a fifth of the 1 ms
//    tick that every component of a deployment shares.
//  - Sensor: one ForceTorqueSensor step (noise, saturation, quantisation, filter) against a
//    naive version of the same model that builds vectors and a distribution on every call, as
//    straightforward code does; the time column is per step.

#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/components/monitoring/needle_insertion_monitor.hpp"
#include "cobra/components/sim/patient_simulator.hpp"
#include "cobra/components/sim/simulated_omni_phantom.hpp"
#include "cobra/components/sim/simulated_robot.hpp"
#include "cobra/components/monitoring/ultrasound_monitor.hpp"
#include "cobra/core/core.hpp"
#include "cobra/kinematics/isur.hpp"
#include "cobra/kinematics/ur5.hpp"
#include "cobra/sim/ft_sensor.hpp"
#include "cobra/sim/needle_tissue.hpp"
#include "cobra/sim/servo.hpp"
#include "cobra/sim/ultrasound.hpp"
#include "cobra/sim/ultrasound_image.hpp"
#include "median_and_worst.hpp"

namespace {

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;  // s
constexpr double kDt = 1e-3;                    // s, 1 kHz

using cobra::bench::maxOf;

void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTimePerRepetition);
}

const std::vector<double> kNeedleStart{0.3, -1.2, 1.5, -1.9, -1.57, 0.2};  // rad
const std::vector<double> kProbeStart{-0.4, -1.3, 1.6, -1.9, -1.57, 0.0};  // rad

/// The puncturing world: everything a puncturing deployment would step in one cycle.
class PuncturingWorld {
 public:
  PuncturingWorld()
      : needle_robot_(cobra::sim::uniformServoModel("needle UR5", needle_solver_.limits(), 0.02, 3.0, 4096.0 * 100),
                      kNeedleStart),
        probe_robot_(cobra::sim::uniformServoModel("probe UR5", probe_solver_.limits(), 0.02, 3.0, 4096.0 * 100),
                     kProbeStart),
        needle_servo_(needle_solver_, needle_robot_),
        probe_servo_(probe_solver_, probe_robot_),
        tissue_(cobra::sim::defaultAbdomen()),
        needle_sensor_(cobra::sim::atiNano17(), 1),
        probe_sensor_(cobra::sim::atiNano43(), 2) {
    needle_servo_.pose(needle_start_);
    probe_servo_.pose(probe_start_);
    // Phantom frame: skin 5 mm ahead of the needle's start, its -z along the needle (tool z).
    world_to_phantom_ = KDL::Frame(needle_start_.M * KDL::Rotation::RotX(std::numbers::pi),
                                   needle_start_.p + needle_start_.M.UnitZ() * 0.005)
                            .Inverse();
  }

  void step() noexcept {
    time_ += kDt;
    // In and out along the tool axis: 0 -> 45 mm -> 0 over 16 s (skin at 5 mm).
    const double phase = std::fmod(time_, 16.0) / 8.0;
    const double advance = 0.045 * (1.0 - std::abs(1.0 - phase));
    KDL::Frame needle_target = needle_start_;
    needle_target.p += needle_start_.M.UnitZ() * advance;
    needle_servo_.command(needle_target);
    probe_servo_.command(probe_start_);
    needle_robot_.step(kDt);
    probe_robot_.step(kDt);

    KDL::Frame needle_pose, probe_pose;
    needle_servo_.pose(needle_pose);
    probe_servo_.pose(probe_pose);
    const KDL::Frame tip = world_to_phantom_ * needle_pose;
    const KDL::Frame probe = world_to_phantom_ * probe_pose;
    const cobra::sim::UltrasoundView view = cobra::sim::observe(probe_model_, tissue_.scenario(), probe, tip);
    const cobra::sim::NeedleForces& forces = tissue_.step(kDt, tip);
    if (forces.flags & cobra::sim::kPunctureEvent) ++punctures_;
    if (view.needle_visible) ++visible_steps_;
    // Sensor frames = tool frames: the wrench of the tissue on the tool, expressed there.
    needle_sensor_.step(kDt, tip.M.Inverse() * KDL::Wrench(forces.force, KDL::Vector::Zero()));
    probe_sensor_.step(kDt, probe.M.Inverse() * KDL::Wrench(view.contact_force, KDL::Vector::Zero()));
  }

  long punctures() const noexcept { return punctures_; }

  double checksum() const noexcept {
    return needle_sensor_.reading().wrench.force.z() + probe_sensor_.reading().wrench.force.z() +
           static_cast<double>(visible_steps_);
  }

 private:
  cobra::kinematics::Ur5Solver needle_solver_;
  cobra::kinematics::Ur5Solver probe_solver_{cobra::kinematics::Ur5Parameters{},
                                             cobra::kinematics::Ur5Solver::defaultLimits(),
                                             KDL::Frame(KDL::Vector(0.8, 0.0, 0.0))};
  cobra::sim::ServoRobot needle_robot_, probe_robot_;
  cobra::sim::CartesianServo needle_servo_, probe_servo_;
  cobra::sim::NeedleTissueModel tissue_;
  cobra::sim::UltrasoundProbeModel probe_model_;
  cobra::sim::ForceTorqueSensor needle_sensor_, probe_sensor_;
  KDL::Frame needle_start_, probe_start_, world_to_phantom_;
  double time_ = 0.0;
  long punctures_ = 0;      // membranes ruptured: proves the needle really goes in
  long visible_steps_ = 0;  // keeps the ultrasound result live
};

void BM_PuncturingWorld(benchmark::State& state) {
  PuncturingWorld world;
  constexpr int kStepsPerIteration = 1000;
  for (auto _ : state) {
    for (int i = 0; i < kStepsPerIteration; ++i) world.step();
    benchmark::DoNotOptimize(world.checksum());
  }
  state.counters["realtime_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kStepsPerIteration * kDt, benchmark::Counter::kIsRate);
  state.counters["punctures"] = static_cast<double>(world.punctures());
}
BENCHMARK(BM_PuncturingWorld)->Name("PuncturingWorld/1s_at_1kHz/two_ur5_phantom_needle_us_two_ft")
    ->Apply(configure)
    ->UseRealTime()  // realtime_factor per wall-clock second
    ->Unit(benchmark::kMillisecond);

/// The component-level puncturing world on the lockstep clock (see the file comment).
class ComponentWorld {
 public:
  explicit ComponentWorld(bool read_image) {
    using cobra::core::connectPorts;
    cobra::kinematics::IsurPuncturingSolver isur_solver;
    KDL::JntArray q(8);
    const double q0[8] = {0.1, 0.1, 0.1, 0.0, 0.0, 0.6, 0.6, 0.0};
    for (unsigned i = 0; i < 8; ++i) q(i) = q0[i];
    isur_solver.forward(q, needle_start_);
    axis_ = needle_start_.M.UnitX();
    const KDL::Rotation needle_frame = needle_start_.M * KDL::Rotation::RotY(std::numbers::pi / 2);
    const KDL::Frame phantom(needle_frame * KDL::Rotation::RotX(std::numbers::pi), needle_start_.p + axis_ * 0.005);
    probe_ = phantom * KDL::Frame(KDL::Rotation(0, 1, 0, 1, 0, 0, 0, 0, -1), KDL::Vector(0.0, 0.02, -0.002));
    cobra::kinematics::Ur5Solver ur5_solver;
    KDL::JntArray u(6);
    const double u0[6] = {0.0, -1.57, 1.57, -1.57, -1.57, 0.0};
    for (unsigned i = 0; i < 6; ++i) u(i) = u0[i];
    KDL::Frame flange;
    ur5_solver.forward(u, flange);
    ur5_.setProperty("base_frame", probe_ * flange.Inverse());
    patient_.setProperty("phantom_pose", phantom);
    for (cobra::core::Component* c : components()) clock_.add(*c, std::chrono::milliseconds(1));
    connectPorts(needle_command_, isur_.port("desCartPose"));
    connectPorts(probe_command_, ur5_.port("desCartPose"));
    connectPorts(isur_.port("trueCartPose"), patient_.port("needleTipPose"));
    connectPorts(ur5_.port("trueCartPose"), patient_.port("probePose"));
    connectPorts(patient_.port("needleWrench"), isur_.port("contactWrench"));
    connectPorts(patient_.port("probeWrench"), ur5_.port("contactWrench"));
    connectPorts(isur_.port("measWrench"), needle_monitor_.port("measWrench"));
    connectPorts(isur_.port("measCartPose"), needle_monitor_.port("measCartPose"));
    connectPorts(patient_.port("needlePlaneDistance"), us_monitor_.port("needlePlaneDistance"));
    connectPorts(patient_.port("needleInImage"), us_monitor_.port("needleInImage"));
    connectPorts(patient_.port("probeContactForce"), us_monitor_.port("probeContactForce"));
    if (read_image) connectPorts(patient_.port("usImage"), image_);
    connectPorts(isur_.port("measWrench"), omni_.port("desWrench"));
    connectPorts(needle_monitor_.port("events"), events_, cobra::core::ConnPolicy::buffer(64));
    connectPorts(us_monitor_.port("events"), events_, cobra::core::ConnPolicy::buffer(64));
    for (cobra::core::Component* c : components()) {
      if (!c->configure() || !c->start()) throw std::runtime_error(c->name() + ": " + c->lastError());
    }
  }

  void step() {
    time_ += kDt;
    const double phase = std::fmod(time_, 16.0) / 8.0;  // 0 -> 45 mm -> 0 over 16 s, skin at 5 mm
    const double advance = 0.045 * (1.0 - std::abs(1.0 - phase));
    needle_command_.write(KDL::Frame(needle_start_.M, needle_start_.p + axis_ * advance));
    probe_command_.write(probe_);
    clock_.advance(std::chrono::milliseconds(1));
    cobra::core::Event e;
    while (events_.read(e) == cobra::core::FlowStatus::NewData) ++events_seen_;
  }
  long events() const { return events_seen_; }

 private:
  std::vector<cobra::core::Component*> components() {
    return {&isur_, &ur5_, &patient_, &needle_monitor_, &us_monitor_, &omni_};
  }

  cobra::core::LockstepClock clock_;
  cobra::components::SimulatedISURRobot isur_{"isur"};
  cobra::components::SimulatedUR5Robot ur5_{"ur5"};
  cobra::components::PatientSimulator patient_{"patient"};
  cobra::components::NeedleInsertionMonitor needle_monitor_{"needleMonitor"};
  cobra::components::UltrasoundMonitor us_monitor_{"usMonitor"};
  cobra::components::SimulatedOmniPhantom omni_{"omni"};
  cobra::core::OutputPort<KDL::Frame> needle_command_{"needleCommand", "", "m"};
  cobra::core::OutputPort<KDL::Frame> probe_command_{"probeCommand", "", "m"};
  cobra::core::InputPort<cobra::core::Event> events_{"events", "", ""};
  cobra::core::InputPort<cobra::types::GrayImage> image_{"image", "", "m"};  // as the OpenIGTLink bridge's
  KDL::Frame needle_start_, probe_;
  KDL::Vector axis_;
  double time_ = 0.0;
  long events_seen_ = 0;
};

void BM_ComponentWorld(benchmark::State& state) {
  ComponentWorld world(state.range(0) != 0);
  constexpr int kStepsPerIteration = 1000;
  for (auto _ : state) {
    for (int i = 0; i < kStepsPerIteration; ++i) world.step();
  }
  const double simulated = static_cast<double>(state.iterations()) * kStepsPerIteration * kDt;  // s
  state.counters["realtime_factor"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["events"] = static_cast<double>(world.events());
}
BENCHMARK(BM_ComponentWorld)->Name("ComponentWorld/1s_at_1kHz/isur_ur5_patient_two_monitors_omni_lockstep")
    ->Arg(0)
    ->Apply(configure)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ComponentWorld)->Name("ComponentWorld/1s_at_1kHz/isur_ur5_patient_two_monitors_omni_lockstep/us_image_read")
    ->Arg(1)
    ->Apply(configure)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_UltrasoundImage(benchmark::State& state) {
  cobra::sim::UltrasoundImageModel model;
  model.width = model.height = static_cast<int>(state.range(0));
  model.spacing_x = model.spacing_y = 0.1 / static_cast<double>(state.range(0));  // m: 100 mm x 100 mm
  const cobra::sim::UltrasoundImager imager(model, cobra::sim::defaultAbdomen(), 7);
  // A needle from (-0.02, 0, 0) to the tumour's centre, the probe 45 mm beyond its tip looking at it.
  const cobra::sim::PhantomScenario phantom = cobra::sim::defaultAbdomen();
  const KDL::Vector entry(-0.02, 0.0, 0.0), target = phantom.tumour_center;
  KDL::Vector along = target - entry;
  along.Normalize();
  const KDL::Vector side = KDL::Vector(0, 0, 1) * along;
  const KDL::Frame tip(KDL::Rotation(side * along, side, along), target);
  const KDL::Vector face(target.x() + 0.045, 0.0, 0.0);
  KDL::Vector beam = target - face;
  beam.Normalize();
  const KDL::Vector array = (KDL::Vector(-1, 0, 0) - beam * -beam.x()) / (KDL::Vector(-1, 0, 0) - beam * -beam.x()).Norm();
  const KDL::Frame probe(KDL::Rotation(array, beam * array, beam), face);
  auto image = std::make_unique<cobra::sim::UltrasoundImage>();
  for (auto _ : state) {
    imager.render(probe, &tip, *image);
    benchmark::DoNotOptimize(image->pixels[image->width * image->height / 2]);
  }
}
BENCHMARK(BM_UltrasoundImage)->Name("UltrasoundImage/render")->Arg(128)->Arg(256)->Apply(configure)->Unit(benchmark::kMillisecond);

/// Thread CPU time, ns.
std::int64_t threadCpuNs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

/// The PatientSimulator alone at 1 kHz (the ComponentWorld's geometry: the probe 20 mm beside the
/// needle's entry, 2 mm into the skin, the needle 20 mm in, in the imaging plane).
/// state.range(0): 0 no image, 1 a band of 1024 px in every update, 2 the whole image in every update.
void BM_PatientUpdate(benchmark::State& state) {
  const KDL::Frame phantom(KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(0.0, 0.0, 0.1));
  const KDL::Frame probe = phantom * KDL::Frame(KDL::Rotation(0, 1, 0, 1, 0, 0, 0, 0, -1), KDL::Vector(0.0, 0.02, -0.002));
  const KDL::Frame tip = phantom * KDL::Frame(KDL::Rotation(0, 1, 0, 1, 0, 0, 0, 0, -1), KDL::Vector(0.0, 0.0, -0.02));
  cobra::core::LockstepClock clock;
  cobra::components::PatientSimulator patient("patient");
  patient.setProperty("phantom_pose", phantom);
  patient.setProperty("tip_to_needle", KDL::Frame::Identity());
  const double rates[] = {0.0, 62.5, 1000.0};
  patient.setProperty("image_rate", rates[state.range(0)]);
  patient.setProperty("image_pixels_per_step", state.range(0) == 2 ? 0 : 1024);
  clock.add(patient, std::chrono::milliseconds(1));
  cobra::core::OutputPort<KDL::Frame> probe_pose{"probePose", "", "m"}, tip_pose{"tipPose", "", "m"};
  cobra::core::InputPort<cobra::types::GrayImage> image{"image", "", "m"};
  cobra::core::connectPorts(probe_pose, patient.port("probePose"));
  cobra::core::connectPorts(tip_pose, patient.port("needleTipPose"));
  cobra::core::connectPorts(patient.port("usImage"), image);
  if (!patient.configure() || !patient.start()) throw std::runtime_error("patient: " + patient.lastError());
  std::int64_t worst = 0;
  for (auto _ : state) {
    probe_pose.write(probe);
    tip_pose.write(tip);
    const std::int64_t before = threadCpuNs();
    clock.advance(std::chrono::milliseconds(1));
    worst = std::max(worst, threadCpuNs() - before);
  }
  state.counters["worst_step_us"] = static_cast<double>(worst) * 1e-3;
}
BENCHMARK(BM_PatientUpdate)->Name("PatientUpdate/no_image")->Arg(0)->Apply(configure)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PatientUpdate)->Name("PatientUpdate/image_band_1024px")->Arg(1)->Apply(configure)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PatientUpdate)->Name("PatientUpdate/whole_image_128x128")->Arg(2)->Apply(configure)->Unit(benchmark::kMicrosecond);

void BM_SensorCobra(benchmark::State& state) {
  cobra::sim::ForceTorqueSensorModel model = cobra::sim::atiNano17();
  model.filter_cutoff_hz = 200.0;
  cobra::sim::ForceTorqueSensor sensor(model, 7);
  const KDL::Wrench w(KDL::Vector(1.0, -2.0, 3.0), KDL::Vector(0.01, 0.02, -0.03));
  for (auto _ : state) benchmark::DoNotOptimize(sensor.step(kDt, w).wrench.force.x());
}
BENCHMARK(BM_SensorCobra)->Name("Sensor/cobra_ForceTorqueSensor")->Apply(configure);

/// The same model as ForceTorqueSensor (bias, low-pass, noise, saturation, quantisation) as
/// straightforward code writes it: vectors per call, a distribution per sample.
struct NaiveSensor {
  cobra::sim::ForceTorqueSensorModel model;
  std::mt19937_64 rng{7};
  std::vector<double> filtered = std::vector<double>(6, 0.0);

  std::vector<double> step(double dt, const KDL::Wrench& w) {
    std::vector<double> input{w.force.x(), w.force.y(), w.force.z(), w.torque.x(), w.torque.y(), w.torque.z()};
    std::vector<double> bias{model.bias.force.x(), model.bias.force.y(), model.bias.force.z(),
                             model.bias.torque.x(), model.bias.torque.y(), model.bias.torque.z()};
    std::vector<double> out(6);
    const double alpha = 1.0 - std::exp(-2.0 * std::numbers::pi * model.filter_cutoff_hz * dt);
    for (std::size_t i = 0; i < 6; ++i) {
      filtered[i] += alpha * (input[i] + bias[i] - filtered[i]);
      std::normal_distribution<double> noise(0.0, model.noise_std[i]);
      const double v = std::clamp(filtered[i] + noise(rng), -model.saturation[i], model.saturation[i]);
      out[i] = model.resolution[i] * std::round(v / model.resolution[i]);
    }
    return out;
  }
};

void BM_SensorNaive(benchmark::State& state) {
  NaiveSensor sensor{cobra::sim::atiNano17()};
  sensor.model.filter_cutoff_hz = 200.0;
  const KDL::Wrench w(KDL::Vector(1.0, -2.0, 3.0), KDL::Vector(0.01, 0.02, -0.03));
  for (auto _ : state) benchmark::DoNotOptimize(sensor.step(kDt, w)[0]);
}
BENCHMARK(BM_SensorNaive)->Name("Sensor/naive_vectors_and_distribution_per_call")->Apply(configure);

}  // namespace

BENCHMARK_MAIN();
