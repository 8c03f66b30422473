#pragma once
/// @file
/// Keeping the lockstep clocks of several processes in step: one simulated run split over
/// processes or hosts (thesis §4.4, each robot controller on its own computer). Core knows no
/// transport: a transport (cobra::dds) implements ClockSync and the run sets it on its clock.

#include <chrono>
#include <string>
#include <vector>

namespace cobra::core {

/// The processes of a distributed lockstep run meet at the end of every LockstepClock::advance:
/// each tells the others it has run every step before `t` and waits until they have too and
/// until the samples they wrote before `t` have arrived in its input ports. A sample written in
/// [t - d, t) by one process is thus read by the others from t on (d: the advance's duration),
/// and two runs with the same inputs give the same traces. Not real-time: it runs on the
/// clock's thread between instants, never inside a component's step.
class ClockSync {
 public:
  virtual ~ClockSync() = default;
  /// Called by LockstepClock::advance at its end, `t` its new now (ns). Returns when every peer
  /// has reached `t` (or was found lost: a peer silent for its lease is given up, reported on the
  /// implementation's events and not waited for again). Must not throw.
  virtual void reached(std::chrono::nanoseconds t) noexcept = 0;
  /// This process has nothing left to do (its task charts ended); it keeps meeting its peers
  /// until each has said the same (or was lost). Told to the peers at the next meeting.
  virtual void setDone(bool done) noexcept = 0;
  /// True when this process's done was told at a meeting, and every peer has said it is done
  /// or was lost: the process may leave (its peers no longer wait for it).
  virtual bool peersDone() const noexcept = 0;
  /// Peers given up so far (their names, in the order they were lost).
  virtual std::vector<std::string> lostPeers() const = 0;
};

}  // namespace cobra::core
