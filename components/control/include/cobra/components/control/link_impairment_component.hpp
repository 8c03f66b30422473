#pragma once
/// @file
/// An impaired master-slave link (thesis §4.5.4: the two-layer teleoperation under "time delays
/// and package loss") as a component between the master side and the slave side of a
/// teleoperation coupling: a thin adapter around cobra::control::LinkImpairment, one per direction.

#include <kdl/frames.hpp>
#include <optional>
#include <string>

#include "cobra/control/link_impairment.hpp"
#include "cobra/core/component.hpp"

namespace cobra::components {

/// Calculation; needs a periodic activity: each update samples what its inputs hold (the newest
/// sample, new or not: the link carries one packet per period and direction, as a teleoperation
/// channel streaming at the control rate does), sends it, and writes what arrived by now. Zero
/// delay, jitter and loss: the outputs are the inputs of the same update.
///
/// Master -> slave: in `masterPose` (KDL.Frame, m), `masterTwist` (KDL.Twist, m/s, rad/s; zero
/// while never written), out `linkedMasterPose`, `linkedMasterTwist` (the same, delayed), sent
/// together once masterPose has data. Slave -> master: in `slaveWrench` (KDL.Wrench, N, N·m),
/// out `linkedSlaveWrench`. Each output holds its last arrived sample until a newer one arrives
/// (a lost or late packet leaves the receiver with the previous one).
///
/// The Passivity layers' energy exchange (Franken et al. 2011) rides in the same packets: in
/// `masterEnergy` (J, the master side's layer's energyOut) and `masterRequest` (bool), out
/// `linkedMasterEnergy`, `linkedMasterRequest` on the slave's side; in `slaveEnergy`,
/// `slaveRequest`, out `linkedSlaveEnergy`, `linkedSlaveRequest` on the master's side. An energy
/// sample is sent once (a sample not new at an update sends 0 J: energy is never duplicated) and
/// written once when its packet arrives; a packet lost or overtaken loses its energy, which left
/// the sender's tank when sent: energy is destroyed, never created.
///
/// Properties: `delay` (s, >= 0, constant one-way delay, both directions), `jitter` (s, >= 0:
/// extra delay drawn uniformly in [0, jitter] per packet), `loss` (1, in [0, 1]: share of the
/// packets lost, per direction), `seed` (the draws; the backward link uses seed + 1),
/// `capacity` (packets in flight per direction, >= 1: with period T it must exceed
/// (delay + jitter) / T, else sends are refused).
/// Counters (int, packets since configure), out: `lostForward`, `lostBackward` (lost by the
/// link), `lateForward`, `lateBackward` (overtaken by a newer packet and discarded),
/// `refusedForward`, `refusedBackward` (the buffer was full).
/// Real time: updateHook reads, sends, receives, writes; allocation-free (the buffers are
/// allocated at configure).
class LinkImpairmentComponent : public core::Component {
 public:
  explicit LinkImpairmentComponent(std::string name);

 protected:
  bool configureHook() override;
  void updateHook() override;
  void cleanupHook() override;

 private:
  struct MasterSample {
    KDL::Frame pose;
    KDL::Twist twist;
    double energy = 0.0;  // J
    bool request = false;
    bool has_pose = false;  // the pose port had data when sent
  };
  struct SlaveSample {
    KDL::Wrench wrench = KDL::Wrench::Zero();
    double energy = 0.0;  // J
    bool request = false;
    bool has_wrench = false;  // the wrench port had data when sent
  };

  core::Property<double> delay_{"delay", 0.0, "s", "constant one-way delay of each direction"};
  core::Property<double> jitter_{"jitter", 0.0, "s", "extra delay drawn uniformly in [0, jitter] per packet"};
  core::Property<double> loss_{"loss", 0.0, "1", "share of the packets lost, per direction, 0..1"};
  core::Property<int> seed_{"seed", 1, "1", "seed of the loss and jitter draws (backward: seed + 1)"};
  core::Property<int> capacity_{"capacity", 4096, "1", "packets in flight per direction, >= 1"};

  core::InputPort<KDL::Frame> master_pose_{"masterPose", "master pose, master side", "m"};
  core::InputPort<KDL::Twist> master_twist_{"masterTwist", "master twist, master side", "m/s, rad/s"};
  core::InputPort<KDL::Wrench> slave_wrench_{"slaveWrench", "wrench for the master, slave side", "N, N·m"};
  core::OutputPort<KDL::Frame> linked_pose_{"linkedMasterPose", "master pose as the slave side receives it", "m"};
  core::OutputPort<KDL::Twist> linked_twist_{"linkedMasterTwist", "master twist as the slave side receives it",
                                             "m/s, rad/s"};
  core::OutputPort<KDL::Wrench> linked_wrench_{"linkedSlaveWrench", "the wrench as the master side receives it",
                                               "N, N·m"};
  core::InputPort<double> master_energy_{"masterEnergy", "energy the master side's tank sends, master side", "J"};
  core::InputPort<bool> master_request_{"masterRequest", "the master side's tank asks for energy, master side", "1"};
  core::InputPort<double> slave_energy_{"slaveEnergy", "energy the slave side's tank sends, slave side", "J"};
  core::InputPort<bool> slave_request_{"slaveRequest", "the slave side's tank asks for energy, slave side", "1"};
  core::OutputPort<double> linked_master_energy_{"linkedMasterEnergy",
                                                 "a packet's energy from the master side's tank, as it arrives", "J"};
  core::OutputPort<bool> linked_master_request_{"linkedMasterRequest",
                                                "the master side's tank asks, as the slave side receives it", "1"};
  core::OutputPort<double> linked_slave_energy_{"linkedSlaveEnergy",
                                                "a packet's energy from the slave side's tank, as it arrives", "J"};
  core::OutputPort<bool> linked_slave_request_{"linkedSlaveRequest",
                                               "the slave side's tank asks, as the master side receives it", "1"};
  core::OutputPort<int> lost_forward_{"lostForward", "master -> slave packets lost", "1"};
  core::OutputPort<int> lost_backward_{"lostBackward", "slave -> master packets lost", "1"};
  core::OutputPort<int> late_forward_{"lateForward", "master -> slave packets overtaken and discarded", "1"};
  core::OutputPort<int> late_backward_{"lateBackward", "slave -> master packets overtaken and discarded", "1"};
  core::OutputPort<int> refused_forward_{"refusedForward", "master -> slave packets refused: buffer full", "1"};
  core::OutputPort<int> refused_backward_{"refusedBackward", "slave -> master packets refused: buffer full", "1"};

  std::optional<control::LinkImpairment<MasterSample>> forward_;
  std::optional<control::LinkImpairment<SlaveSample>> backward_;
  MasterSample master_, arrived_master_;
  SlaveSample slave_, arrived_slave_;
};

}  // namespace cobra::components
