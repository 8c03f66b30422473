#pragma once
/// @file
/// `IgtlBridge` (role Bridge): cobra's end of an OpenIGTLink connection (TCP, port 18944) to a
/// navigation program, 3D Slicer or PLUS (thesis §4.2: the sensing and planning module feeds the
/// controllers). What travels, and to which ports, is set by mapping strings in the deployment
/// file, parsed at configure into ports:
///   send_transforms    "NeedleTip=needleTip, Probe=probePose"  KDL.Frame in-ports (world, m) -> TRANSFORM
///                      every send_period s (mm on the wire)
///   receive_transforms "Registration=abdomenFrame"             TRANSFORM -> KDL.Frame out-ports (m)
///   plan_device        "Plan"                                   POINT of that device -> out-port `plan`
///   requests           "START=e_nav_start, ABORT=e_nav_abort"   STRING of device "Request" whose text
///                      is a key -> that event
///   images             "USImage=usImage"                        Imaging.GrayImage in-ports -> IMAGE, each
///                      new image at most once per send_period
///   send_strings       "Refusal=refusal"                        string in-ports -> STRING of the device, each
///                      new line once (its first 255 characters)
/// and always: in-port `taskState` (a change, and each new peer -> STATUS of device "TaskState",
/// the path as status string), event in-port `inputEvents` (each event -> STRING of device "Event", its name; not
/// `events`, which is every component's own out-port).
///
/// Anything else received (an unmapped device, a request text that is no key, a bad CRC, garbage, an
/// oversized or unknown message) is dropped and counted (`dropped_messages`, the last reason in
/// `dropped_reason`), never an event. `e_igtl_connected` when a peer connects, `e_igtl_peer_lost`
/// when it disconnects or stays silent `peer_timeout` s. Socket I/O runs on the IgtlLink thread;
/// updateHook only moves records through lock-free rings and triple buffers: it allocates
/// nothing, blocks on nothing and throws nothing.

#include <memory>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/bridges/igtl_link.hpp"
#include "cobra/core/component.hpp"
#include "cobra/types/gray_image.hpp"
#include "cobra/types/point_list.hpp"

namespace cobra::bridges {

class IgtlBridge : public core::Component {
 public:
  explicit IgtlBridge(std::string name);
  ~IgtlBridge() override;

 protected:
  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;
  void cleanupHook() override;

 private:
  struct SendTransform {
    std::string device;
    std::unique_ptr<core::InputPort<KDL::Frame>> port;
  };
  struct ReceiveTransform {
    std::string device;
    std::unique_ptr<core::OutputPort<KDL::Frame>> port;
  };
  struct Request {
    std::string key;
    std::string event;
  };
  struct SendString {
    std::string device;
    std::unique_ptr<core::InputPort<std::string>> port;
  };
  struct Image {
    std::string device;
    std::unique_ptr<core::InputPort<types::GrayImage>> port;
  };

  /// Characters of a string in-port's line read without allocating (reserved at configure); a
  /// longer line is read whole (one allocation) and its first 255 characters sent.
  static constexpr std::size_t kLineCapacity = 4096;

  int localPort();
  bool parseMappings();
  void removeMappedPorts();
  void dispatch(const igtl::Message& message) noexcept;
  void queue(const IgtlOutMessage& message) noexcept;
  void drop(DropReason reason) noexcept;
  void sendPeriodic(std::uint64_t stamp) noexcept;
  bool reportLink() noexcept;  // emits the link's events; true when a peer connected (and is still there)
  void updateCounters() noexcept;

  core::OutputPort<types::PointList> plan_{"plan", "the plan's points (POINT messages of plan_device), world", "m"};
  core::InputPort<core::TaskState> task_state_{"taskState", "the task chart's state, sent as STATUS on change and to each new peer", ""};
  core::InputPort<core::Event> input_events_{"inputEvents", "events sent as STRING messages of device \"Event\"", ""};

  core::Property<std::string> role_{"role", "server", "", "\"server\" (the navigation program connects) or \"client\""};
  core::Property<std::string> host_{"host", "127.0.0.1", "", "client: the server's address; server: the address to bind"};
  core::Property<int> port_{"port", 18944, "1", "TCP port (server: 0 binds an ephemeral one, see localPort)"};
  core::Property<double> send_period_{"send_period", 0.05, "s", "period of the outgoing TRANSFORM and IMAGE messages"};
  core::Property<double> peer_timeout_{"peer_timeout", 0.0, "s", "a peer silent this long is dropped (e_igtl_peer_lost); 0: never"};
  core::Property<int> max_message_bytes_{"max_message_bytes", 1 << 20, "byte", "bigger received messages are dropped"};
  core::Property<std::string> send_transforms_{"send_transforms", "", "", "DEVICE=port, ...: KDL.Frame in-ports sent as TRANSFORM"};
  core::Property<std::string> receive_transforms_{"receive_transforms", "", "", "DEVICE=port, ...: TRANSFORM to KDL.Frame out-ports"};
  core::Property<std::string> plan_device_{"plan_device", "", "", "device whose POINT messages go to `plan` (\"\": none)"};
  core::Property<std::string> requests_{"requests", "", "", "KEY=event, ...: STRING of device Request whose text is KEY emits the event"};
  core::Property<std::string> images_{"images", "", "", "DEVICE=port, ...: Imaging.GrayImage in-ports sent as IMAGE"};
  core::Property<std::string> send_strings_{"send_strings", "", "",
                                            "DEVICE=port, ...: string in-ports, each new line sent as STRING"};
  core::Property<int> received_messages_{"received_messages", 0, "1", "messages received and used"};
  core::Property<int> sent_messages_{"sent_messages", 0, "1", "messages written to a peer"};
  core::Property<int> dropped_messages_{"dropped_messages", 0, "1", "messages dropped (received or to send)"};
  core::Property<std::string> dropped_reason_{"dropped_reason", "", "", "why the last message was dropped"};

  std::vector<SendTransform> send_;
  std::vector<ReceiveTransform> receive_;
  std::vector<Request> requests_map_;
  std::vector<Image> image_ports_;
  std::vector<SendString> strings_;
  std::string line_;  // a received line; capacity reserved at configure (kLineCapacity)
  std::unique_ptr<IgtlLink> link_;
  std::unique_ptr<igtl::Message> scratch_;   // the received message being dispatched
  std::int64_t next_send_ns_ = 0;
  std::uint64_t seen_connections_ = 0, seen_losses_ = 0, seen_link_drops_ = 0;
  int used_ = 0;        // messages received and used
  int own_drops_ = 0;   // messages the bridge itself dropped
  core::TaskState last_state_;
  bool have_state_ = false;
};

}  // namespace cobra::bridges
