// Navigated puncturing end to end (README.md "Navigated puncturing"): puncturing.lua with the
// global `navigation`, run on the lockstep clock through the runner's API as procedure_test.cpp
// does, with a navigation peer written on libOpenIGTLink (as 3D Slicer and PLUS are) on its own
// thread: it connects to the IgtlBridge `Navigation`, sends the registration and the two_needles
// plan (cryo_plan.txt's points, in mm), and records what cobra sends back (tool poses, task
// states, events, refusals). The run waits for the peer's first messages before it steps (the
// observer below), and the needle chart waits for the plan (WaitNavigation), so the run is
// deterministic: the same placements as the file-driven procedure.

#include "cobra/run/runner.hpp"

#include <gtest/gtest.h>

#include "igtl_test_peer.hpp"
#include "procedure_expectations.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <condition_variable>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "cobra/core/component.hpp"
#include "cobra/core/introspection.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using namespace testing;
using namespace std::chrono_literals;
using bridges::test::PeerPoint;

/// A pose the peer received: its OpenIGTLink timestamp (s of run time) and the pose (m).
struct Stamped {
  double t = 0.0;
  KDL::Frame pose;
};

/// What the peer does beyond sending the registration and the plan.
struct PeerScript {
  std::vector<PeerPoint> plan;  // mm, frame A
  float registration_z = 100.0F;  // mm: A's origin in the world (two_needles: 0, 0, 0.1 m)
  float registration_x = 0.0F;    // mm
  bool send_plan = true;
  /// On the first task state containing this: bad messages, then garbage (the bridge drops the
  /// connection); the peer connects again, then leaves for good at `leave_in_state`.
  std::string misbehave_in_state;
  std::string leave_in_state;
  /// On the first task state containing this, the peer sends the request `request` (STRING "Request").
  std::string request_in_state;
  std::string request;
};

/// two_needles' cryo_plan.txt as navigation points (mm, frame A).
std::vector<PeerPoint> twoNeedles() {
  return {{"n1.entry", "plan", -20, -6, 0}, {"n1.target", "plan", -5, 0, -58},
          {"n2.entry", "plan", -10, 8, 0}, {"n2.target", "plan", 5, 0, -62}};
}

/// A peer that sends `plan` and the two_needles registration.
PeerScript sending(std::vector<PeerPoint> plan) {
  PeerScript script;
  script.plan = std::move(plan);
  return script;
}

/// The navigation program: a libOpenIGTLink client on its own thread.
class NavigationPeer {
 public:
  explicit NavigationPeer(PeerScript script) : script_(std::move(script)) {}
  ~NavigationPeer() { stop(); }

  void start(int port) {
    port_ = port;
    thread_ = std::thread([this] { run(); });
  }
  /// Blocks (wall clock, at most 30 s) until the registration and plan are sent.
  bool waitSent() {
    std::unique_lock lock(mutex_);
    return sent_cv_.wait_for(lock, 30s, [&] { return sent_; });
  }
  void stop() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
  }

  // Read after stop().
  std::vector<Stamped> needle, probe;
  std::vector<std::string> states;                            // STATUS of TaskState
  std::vector<std::pair<std::string, std::string>> strings;   // STRING: device, text
  int images = 0;
  int connections = 0;
  int states_at_reconnect = -1;  // how many states had come when the peer connected again

 private:
  static double seconds(::igtl::MessageBase* m) {
    unsigned int sec = 0, frac = 0;
    m->GetTimeStamp(&sec, &frac);
    return sec + frac / 4294967296.0;
  }
  static KDL::Frame frame(const ::igtl::Matrix4x4& m) {
    return KDL::Frame(KDL::Rotation(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]),
                      KDL::Vector(m[0][3] * 1e-3, m[1][3] * 1e-3, m[2][3] * 1e-3));
  }

  ::igtl::ClientSocket::Pointer connect() {
    ::igtl::ClientSocket::Pointer socket = ::igtl::ClientSocket::New();
    for (int attempt = 0; attempt < 3000 && !stopping_; ++attempt) {
      if (socket->ConnectToServer("127.0.0.1", port_) == 0) {
        socket->SetReceiveTimeout(100);
        ++connections;
        return socket;
      }
      std::this_thread::sleep_for(10ms);
    }
    return nullptr;
  }
  static void send(::igtl::ClientSocket* socket, const std::vector<std::uint8_t>& bytes) {
    socket->Send(bytes.data(), static_cast<int>(bytes.size()));
  }

  void misbehave(::igtl::ClientSocket* socket) {
    std::vector<std::uint8_t> bad_crc = bridges::test::transformBytes("Registration", 0.5F, 50, 50, 150);
    bad_crc.back() ^= 0xFF;
    send(socket, bad_crc);                                                        // bad_crc
    send(socket, bridges::test::positionBytes("Tracker"));                        // unknown_type
    send(socket, bridges::test::stringBytes("Request", "HELLO"));                 // unmapped
    send(socket, bridges::test::stringBytes("Chat", "hello from the navigation"));  // unknown_device
    std::vector<PeerPoint> many(40, PeerPoint{"fiducial", "plan", 1, 2, 3});      // 40 x 136 bytes
    send(socket, bridges::test::pointBytes("Plan", many));                        // oversized
    // A valid registration mid-procedure: used by the bridge, changes nothing (taken once).
    send(socket, bridges::test::transformBytes("Registration", 0.3F, 30, 0, 100));
    std::mt19937 random(7);
    std::vector<std::uint8_t> garbage(96);
    for (auto& b : garbage) b = static_cast<std::uint8_t>(random());
    garbage[0] = 0x7F;  // not version 1 or 2: a bad header, the bridge drops the connection
    send(socket, garbage);
  }

  void run() {
    ::igtl::ClientSocket::Pointer socket = connect();
    if (!socket) return;
    send(socket.GetPointer(), bridges::test::transformBytes("Registration", 0.0F, script_.registration_x, 0.0F,
                                                             script_.registration_z));
    if (script_.send_plan) send(socket.GetPointer(), bridges::test::pointBytes("Plan", script_.plan));
    {
      std::lock_guard lock(mutex_);
      sent_ = true;
    }
    sent_cv_.notify_all();
    bool misbehaved = false, requested = false;
    while (!stopping_ && socket) {
      std::string type, device;
      const std::vector<std::uint8_t> bytes = bridges::test::receiveMessage(socket.GetPointer(), type, device);
      if (bytes.empty()) {
        if (misbehaved && states_at_reconnect < 0) {  // the bridge dropped us: connect again
          socket->CloseSocket();
          socket = connect();
          states_at_reconnect = static_cast<int>(states.size());
        }
        continue;
      }
      if (type == "TRANSFORM") {
        auto m = bridges::test::unpack<::igtl::TransformMessage>(bytes);
        if (!m) continue;
        ::igtl::Matrix4x4 matrix;
        m->GetMatrix(matrix);
        (device == "NeedleTip" ? needle : probe).push_back({seconds(m.GetPointer()), frame(matrix)});
      } else if (type == "STATUS") {
        auto m = bridges::test::unpack<::igtl::StatusMessage>(bytes);
        if (!m) continue;
        states.emplace_back(m->GetStatusString());
        const std::string& state = states.back();
        if (!script_.request_in_state.empty() && !requested && state.find(script_.request_in_state) != std::string::npos) {
          requested = true;
          send(socket.GetPointer(), bridges::test::stringBytes("Request", script_.request));
        }
        if (!script_.misbehave_in_state.empty() && !misbehaved && state.find(script_.misbehave_in_state) != std::string::npos) {
          misbehaved = true;
          misbehave(socket.GetPointer());
        } else if (!script_.leave_in_state.empty() && states_at_reconnect >= 0 &&
                   state.find(script_.leave_in_state) != std::string::npos) {
          socket->CloseSocket();  // the navigation program is gone
          return;
        }
      } else if (type == "STRING") {
        auto m = bridges::test::unpack<::igtl::StringMessage>(bytes);
        if (m) strings.emplace_back(device, m->GetString());
      } else if (type == "IMAGE") {
        if (device == "USImage") ++images;
      }
    }
    if (socket) socket->CloseSocket();
  }

  PeerScript script_;
  int port_ = 0;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::mutex mutex_;
  std::condition_variable sent_cv_;
  bool sent_ = false;
};

/// Watches the run: starts the peer on the bridge's port once the deployment is up, holds the
/// run's first step until the peer has sent (so the plan is there long before the chart asks),
/// holds each step until the bridge's link has written what was queued (the run does not outpace
/// the peer), and records both robots' measured poses every step, to compare with what the peer
/// received.
class Watch : public RunObserver {
 public:
  explicit Watch(NavigationPeer& peer) : peer_(peer) {}
  void attach(const RunContext& run) override {
    navigation_ = &run.registry.get("Navigation");
    has_image_ = run.registry.get("Patient").findPort("usImage") != nullptr;
    core::connectPorts(run.registry.get("ISUR").port("measCartPose"), needle_in_);
    core::connectPorts(run.registry.get("UR5").port("measCartPose"), probe_in_);
    peer_.start(navigation_->call<int>("localPort"));
  }
  void step(const StepView& now) override {
    if (!released_) {
      released_ = true;
      sent_ = peer_.waitSent();
      std::this_thread::sleep_for(50ms);  // loopback: the link thread has the bytes long before
    }
    // The lockstep run goes faster than the socket: it waits for the bridge's link to have
    // written what was queued (a full queue would drop messages), up to 5 s of wall time.
    // (Only while a peer is connected: without one the link discards the queue every 50 ms.)
    for (int i = 0; i < 50000 && peer_connected_ && navigation_->call<int>("pendingMessages") > 0; ++i)
      std::this_thread::sleep_for(100us);
    const auto k = static_cast<std::size_t>(std::llround(now.t * 1000.0));
    if (needle_at_.size() <= k) {
      needle_at_.resize(k + 1);
      probe_at_.resize(k + 1);
    }
    (void)needle_in_.read(needle_at_[k]);
    (void)probe_in_.read(probe_at_[k]);
  }
  void event(double, const std::string& source, const std::string& name) override {
    if (source == "Navigation" && name == "e_igtl_connected") peer_connected_ = true;
    if (source == "Navigation" && name == "e_igtl_peer_lost") peer_connected_ = false;
  }
  bool nextInput(std::size_t&) override { return false; }
  std::vector<std::string> finished(const RunResult&) override {
    received_ = navigation_->getProperty<int>("received_messages");
    dropped_ = navigation_->getProperty<int>("dropped_messages");
    return {};
  }

  /// m: the largest difference (position, and rotation angle as 1 mrad ~ 1 um) between each pose
  /// the peer received and the robot's measured pose recorded `lag` steps after its timestamp's,
  /// for the lag (0, 1 or 2 steps) that fits every pose best: one lag for the whole run. (The
  /// observer's step time and the bridge's clock at its update are one step apart: lag 1.)
  double worstDifference(const std::vector<Stamped>& received, bool needle) const {
    const auto& at = needle ? needle_at_ : probe_at_;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t lag : {0u, 1u, 2u}) {
      double worst = 0.0;
      for (const Stamped& s : received) {
        const auto k = static_cast<std::size_t>(std::llround(s.t * 1000.0));
        if (k + 3 >= at.size()) return std::numeric_limits<double>::infinity();
        const KDL::Frame& m = at[k + lag];
        KDL::Vector axis;
        const double d = std::max((s.pose.p - m.p).Norm(), 0.001 * (m.M.Inverse() * s.pose.M).GetRotAngle(axis));
        worst = std::max(worst, d);
      }
      best = std::min(best, worst);
    }
    return best;
  }

  bool sent_ = false;
  bool has_image_ = false;  // the Patient has its usImage port: the bridge sends it as IMAGE
  int received_ = -1, dropped_ = -1;

 private:
  NavigationPeer& peer_;
  core::Component* navigation_ = nullptr;
  core::InputPort<KDL::Frame> needle_in_{"needle_in", "", "m"};
  core::InputPort<KDL::Frame> probe_in_{"probe_in", "", "m"};
  std::vector<KDL::Frame> needle_at_, probe_at_;  // per 1 ms step
  bool released_ = false;
  bool peer_connected_ = false;
};

/// The two-needle procedure navigated by `peer`: the bridge on an ephemeral port, poses at 20 Hz.
RunOptions navigated(Watch& watch, const std::string& navigation = "{ port = 0, send_period = 0.05 }") {
  RunOptions o = options("two_needles");
  o.before_lua = "navigation = " + navigation;
  o.observer = &watch;
  return o;
}

std::size_t countStrings(const NavigationPeer& peer, const std::string& device, const std::string& text) {
  return static_cast<std::size_t>(std::count(peer.strings.begin(), peer.strings.end(), std::pair{device, text}));
}

TEST(NavigatedPuncturing, ThePlanAndRegistrationFromTheNavigationPlaceBothNeedlesAsTheFilesDo) {
  const RunResult files = runApp(options("two_needles"));
  ASSERT_TRUE(files.completed()) << files.reason;

  NavigationPeer peer(sending(twoNeedles()));
  Watch watch(peer);
  RunOptions o = navigated(watch);
  o.report_folder =  // per process: other checkouts may run the same test at the same time
      std::filesystem::temp_directory_path() / ("cobra_puncturing_navigated_" + std::to_string(::getpid()));
  std::filesystem::remove_all(o.report_folder);
  const RunResult r = runApp(o);
  peer.stop();
  ASSERT_TRUE(watch.sent_);
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  const SummaryValue& placed = r.value("placement error per needle");
  const SummaryValue& from_files = files.value("placement error per needle");
  ASSERT_EQ(placed.values.size(), from_files.values.size());
  for (std::size_t i = 0; i < placed.values.size(); ++i)
    EXPECT_NEAR(placed.values[i], from_files.values[i], 0.05) << "needle " << i + 1 << " (mm)";
  expectNoCommandJump(r);
  expectFaithful(r);
  expectTanksHeld(o.report_folder);
  // The chart waited for the navigation, said what it took, then verified the whole procedure.
  expectInOrder(r, {"needle > root.WaitIceballConfig", "Surgeon: e_iceball_configured", "needle > root.WaitNavigation",
                    "NeedleFrames: e_navigation_received", "NeedlePlanner: e_procedure_verified",
                    "needle > root.MakeRoomForProbe", "needle > root.Done", "us > root.Done"});
  EXPECT_EQ(count(r, "Navigation: e_igtl_connected"), 1u);
  EXPECT_EQ(watch.received_, 2) << "the registration and the plan";

  // The tool poses at 20 Hz, equal to the robots' measured poses (float mm on the wire).
  ASSERT_GT(peer.needle.size(), 1000u);
  ASSERT_GT(peer.probe.size(), 1000u);
  for (const auto* poses : {&peer.needle, &peer.probe})
    for (std::size_t i = 1; i < poses->size(); ++i)
      ASSERT_NEAR((*poses)[i].t - (*poses)[i - 1].t, 0.05, 1e-6) << i;
  EXPECT_NEAR(peer.needle.back().t, r.duration, 0.1);
  EXPECT_LE(watch.worstDifference(peer.needle, true), 1e-6);
  EXPECT_LE(watch.worstDifference(peer.probe, false), 1e-6);
  // The needle chart's states as STATUS, its events as STRING.
  ASSERT_FALSE(peer.states.empty());
  EXPECT_EQ(peer.states.back(), "root.Done");
  for (const char* state : {"root.WaitNavigation", "root.VerifyingProcedure", "root.WaitCryoCycle"})
    EXPECT_NE(std::find(peer.states.begin(), peer.states.end(), state), peer.states.end()) << state;
  EXPECT_EQ(countStrings(peer, "Event", "e_needle_placed"), 2u);
  EXPECT_EQ(countStrings(peer, "Event", "e_needle_task_done"), 1u);
  for (const auto& [device, text] : peer.strings) EXPECT_NE(device, "Refusal") << text;
  EXPECT_EQ(peer.connections, 1);
  // The ultrasound image, where the simulated patient makes one.
  if (watch.has_image_)
    EXPECT_GT(peer.images, 0);
  else
    EXPECT_EQ(peer.images, 0);
}

// The peer's ABORT (declared: e_navigation_abort) stops both charts where they are; a request the
// application does not declare is dropped (the misbehaving peer's HELLO, below).
TEST(NavigatedPuncturing, ThePeersAbortRequestStopsTheProcedureSafely) {
  PeerScript script = sending(twoNeedles());
  script.request_in_state = "root.WaitUSPositioning";
  script.request = "ABORT";
  NavigationPeer peer(script);
  Watch watch(peer);
  const RunResult r = runApp(navigated(watch));
  peer.stop();
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_CONTAINS(r.reason, "needle chart stopped safely in root.WaitUSPositioning: Navigation: e_navigation_abort at");
  expectInOrder(r, {"needle > root.WaitUSPositioning", "Navigation: e_navigation_abort", "needle > root.SafeStop",
                    "us > root.SafeStop"});
  EXPECT_EQ(count(r, "needle > root.InsertingNeedles.MoveToSkin.Approach"), 0u);
  ASSERT_FALSE(peer.states.empty());
  EXPECT_EQ(peer.states.back(), "root.SafeStop");
}

// Bad messages mid-procedure are dropped and counted; garbage loses the connection, the peer
// comes back and gets the task state at once, then leaves for good: the procedure goes on with
// the plan and registration it verified (the application's reaction to e_igtl_peer_lost).
TEST(NavigatedPuncturing, APeerThatMisbehavesThenDisappearsMidProcedureLeavesTheProcedureToComplete) {
  PeerScript script = sending(twoNeedles());
  script.misbehave_in_state = "root.InsertingNeedles.MoveToTumor";
  script.leave_in_state = "root.ExtractingNeedle";
  NavigationPeer peer(script);
  Watch watch(peer);
  const RunResult r = runApp(navigated(watch, "{ port = 0, max_message_bytes = 4096 }"));
  peer.stop();
  ASSERT_TRUE(r.completed()) << r.reason;
  expectPlaced(r, 2);
  expectFaithful(r);
  expectInOrder(r, {"Navigation: e_igtl_connected", "needle > root.InsertingNeedles.MoveToTumor",
                    "Navigation: e_igtl_peer_lost", "Navigation: e_igtl_connected", "Navigation: e_igtl_peer_lost",
                    "needle > root.Done", "us > root.Done"});
  EXPECT_EQ(count(r, "Navigation: e_igtl_peer_lost"), 2u);
  EXPECT_EQ(peer.connections, 2);
  // The new connection got the current state at once.
  ASSERT_GE(peer.states_at_reconnect, 0);
  ASSERT_GT(peer.states.size(), static_cast<std::size_t>(peer.states_at_reconnect));
  EXPECT_NE(peer.states[static_cast<std::size_t>(peer.states_at_reconnect)].find("root."), std::string::npos);
  // bad CRC, unknown type, unmapped request, unknown device, oversized; the garbage's bad header.
  EXPECT_GE(watch.dropped_, 6);
  EXPECT_EQ(watch.received_, 3) << "the registration and the plan, and the later registration";
}

// A target outside the tumour (and the phantom): refused before anything moves, naming the
// needle and why; the refusal line reaches the peer.
TEST(NavigatedPuncturing, APlanWithATargetOutsideThePhantomIsRefusedBeforeAnyMotionAndThePeerIsTold) {
  std::vector<PeerPoint> plan = twoNeedles();
  plan[3] = {"n2.target", "plan", 5, 0, -190};  // 10 cm below the phantom's bottom
  NavigationPeer peer(sending(plan));
  Watch watch(peer);
  const RunResult r = runApp(navigated(watch));
  peer.stop();
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  const std::string line = "navigation refused: navigation plan:3: needle 'n2': target is 130.1 mm from the tumour "
                           "centre, outside its radius 12.0 mm";
  EXPECT_CONTAINS(r.reason, "needle chart stopped safely in root.WaitNavigation: NeedleFrames: e_navigation_refused at");
  EXPECT_CONTAINS(r.reason, "NeedleFrames.navigationStatus(): " + line);
  expectInOrder(r, {"needle > root.WaitNavigation", "NeedleFrames: e_navigation_refused",
                    "NeedleTaskSup: e_needle_procedure_refused", "needle > root.SafeStop", "us > root.SafeStop"});
  EXPECT_EQ(count(r, "needle > root.VerifyingProcedure"), 0u);
  EXPECT_EQ(count(r, "needle > root.MakeRoomForProbe"), 0u);
  EXPECT_EQ(count(r, "us > root.MoveToSkin.Approach"), 0u);
  EXPECT_EQ(countStrings(peer, "Refusal", line), 1u);
}

// A plan that passes the plan's checks but that the robots cannot carry out: n2 leans the other
// way (toward -x), and the whole procedure's verification refuses it before anything moves; the
// needle planner's refusal line (its first 255 characters, a STRING's) reaches the peer.
TEST(NavigatedPuncturing, APlanTheVerificationRefusesStopsBeforeAnyMotionAndThePeerIsToldWhy) {
  std::vector<PeerPoint> plan = twoNeedles();
  plan[2] = {"n2.entry", "plan", 30, 0, 0};
  plan[3] = {"n2.target", "plan", -5, 0, -60};
  NavigationPeer peer(sending(plan));
  Watch watch(peer);
  const RunResult r = runApp(navigated(watch));
  peer.stop();
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  EXPECT_CONTAINS(r.reason, "needle chart stopped safely in root.VerifyingProcedure: NeedlePlanner: e_procedure_refused");
  const std::string start = "needle n2 (2 of 2), task state 'root.InsertingNeedles.MoveToSkin.Approach' (";
  EXPECT_CONTAINS(r.reason, "NeedlePlanner.lastRefusal(): " + start);
  // (The log may give an event before the state entry of the same step.)
  expectInOrder(r, {"NeedleFrames: e_navigation_received", "NeedlePlanner: e_procedure_refused",
                    "needle > root.VerifyingProcedure", "needle > root.SafeStop", "us > root.SafeStop"});
  EXPECT_EQ(count(r, "needle > root.MakeRoomForProbe"), 0u);
  std::vector<std::string> refusals;
  for (const auto& [device, text] : peer.strings)
    if (device == "Refusal") refusals.push_back(text);
  ASSERT_EQ(refusals.size(), 1u);
  EXPECT_EQ(refusals[0].rfind(start, 0), 0u) << refusals[0];
  EXPECT_EQ(refusals[0].size(), 255u) << "a longer line: its first 255 characters";
  EXPECT_CONTAINS(r.reason, refusals[0]);
}

// A registration the controllers cannot take: 3 cm off the one the planning scene, the monitors
// and the patient were set up with.
TEST(NavigatedPuncturing, ARegistrationFarFromThePlanningScenesIsRefusedNamingHowFar) {
  PeerScript script = sending(twoNeedles());
  script.registration_x = 30.0F;
  NavigationPeer peer(script);
  Watch watch(peer);
  const RunResult r = runApp(navigated(watch));
  peer.stop();
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  const std::string line = "navigation refused: registration: frame A lies 30.0 mm and 0.00 deg from the preoperative "
                           "abdomen the planning scene, the monitors and the patient were set up with; at most 2.0 mm "
                           "and 1.00 deg can be taken";
  EXPECT_CONTAINS(r.reason, "NeedleFrames.navigationStatus(): " + line);
  EXPECT_EQ(count(r, "needle > root.MakeRoomForProbe"), 0u);
  EXPECT_EQ(countStrings(peer, "Refusal", line), 1u);
}

// No plan comes (the peer sends only the registration): the wait ends in the safe stop at the
// timeout (120 s by default), naming what did not come. The bridge from the command line's way:
// COBRA_NAVIGATION_PORT (0: an ephemeral port).
TEST(NavigatedPuncturing, APlanThatNeverComesEndsTheWaitInTheSafeStopNamingIt) {
  PeerScript script = sending(twoNeedles());
  script.send_plan = false;
  NavigationPeer peer(script);
  Watch watch(peer);
  ASSERT_EQ(::setenv("COBRA_NAVIGATION_PORT", "0", 1), 0);
  RunOptions o = options("two_needles");
  o.observer = &watch;
  const RunResult r = runApp(o);
  ::unsetenv("COBRA_NAVIGATION_PORT");
  peer.stop();
  ASSERT_EQ(r.outcome, Outcome::SafeStop) << r.reason;
  const std::string line = "navigation timed out: no plan (POINT) from the navigation within 120 s";
  EXPECT_CONTAINS(r.reason, "needle chart stopped safely in root.WaitNavigation: NeedleFrames: e_navigation_timeout at");
  EXPECT_CONTAINS(r.reason, "NeedleFrames.navigationStatus(): " + line);
  EXPECT_NEAR(r.duration, 121.0, 0.1) << "s: the surgeon's e_iceball_configured at 1 s, then 120 s";
  EXPECT_EQ(countStrings(peer, "Refusal", line), 1u);
  EXPECT_EQ(count(r, "needle > root.VerifyingProcedure"), 0u);
}

}  // namespace
}  // namespace cobra::run
