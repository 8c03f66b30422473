#pragma once
/// @file
/// The thesis' OmniPhantom Bridge (§4.5.9): talks over TCP to the stand-alone application that
/// drives the Phantom Omni, through an OmniClient service thread.

#include <memory>

#include <kdl/frames.hpp>

#include "cobra/bridges/comm_watchdog.hpp"
#include "cobra/bridges/omni_tcp.hpp"
#include "cobra/core/component.hpp"

namespace cobra::bridges {

/// Bridge component. Frames: the application reports the stylus in the device frame D; the ports
/// use the base frame B with B_T_D = `origin_pose_offset`: measCartPose = offset · pose_D,
/// measTwist and desWrench are rotated by the offset's rotation (the Omni renders a force at the
/// stylus point, so no moment transfer). Every update: a new desWrench goes to the application;
/// the latest valid state is published (again every update while no newer one comes).
/// `e_comm_timeout` after `timeout` s without a new valid state (counted from start, so also
/// while (re)connecting), `e_comm_restored` at the first one after that. The client reconnects
/// after the peer drops. Real time: the update is allocation-free and never blocks.
class OmniPhantomBridge : public core::Component {
 public:
  explicit OmniPhantomBridge(std::string name);
  ~OmniPhantomBridge() override;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;
  void cleanupHook() override;

 private:
  int rejectedCount(std::string reason);
  int acceptedCount();
  int connections();

  core::InputPort<KDL::Wrench> des_wrench_{"desWrench", "force to render on the surgeon's hand, base frame",
                                           "N, N·m"};
  core::OutputPort<KDL::Frame> meas_cart_pose_{"measCartPose", "stylus pose, base frame", "m"};
  core::OutputPort<KDL::Twist> meas_twist_{"measTwist", "stylus twist, base frame", "m/s, rad/s"};
  core::OutputPort<int> status_buttons_{"statusButtons", "stylus buttons: bit 0 first, bit 1 second", "1"};

  core::Property<std::string> host_address_{"host_address", "127.0.0.1", "", "address of the Omni application"};
  core::Property<int> host_port_{"host_port", 0, "1", "TCP port of the Omni application"};
  core::Property<KDL::Frame> origin_pose_offset_{"origin_pose_offset", KDL::Frame::Identity(), "m",
                                                 "pose of the device frame in the base frame of the ports"};
  core::Property<double> timeout_{"timeout", 0.1, "s", "without a new valid state this long: e_comm_timeout"};
  core::Property<double> max_delay_{"max_delay", 0.05, "s", "states delayed more than this are rejected, 0: no check"};
  core::Property<double> reconnect_period_{"reconnect_period", 0.05, "s", "wait between connection attempts"};

  std::unique_ptr<OmniClient> client_;
  CommWatchdog watchdog_;
  std::uint64_t last_version_ = 0;
  bool have_state_ = false;
  KDL::Frame offset_;
  KDL::Frame pose_;
  KDL::Twist twist_;
  int buttons_ = 0;
};

}  // namespace cobra::bridges
