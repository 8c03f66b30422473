#pragma once
/// @file
/// How a component (a deployment or configuration supervisor) asks the Configurator that made
/// it to switch deployments and configurations while everything runs (thesis §2.2.3, Fig. 2.6).
///
/// A switch stops, starts and reconnects components, so it cannot happen inside a component's
/// step. The request is therefore queued from the real-time step (no allocation, no lock) and
/// carried out by the Configurator between two steps: on the lockstep clock between two
/// instants, in real time on the Configurator's service thread. The answer comes back through
/// `onRequestDone`, which supervisors turn into events for their chart.

#include <array>
#include <atomic>
#include <cstdint>
#include <string_view>

#include "cobra/core/bounded_string.hpp"

namespace cobra::deploy {

class Configurator;

/// One request: apply deployment or configuration `name`.
struct SwitchRequest {
  enum class Kind : std::uint8_t { Deployment, Configuration };
  Kind kind = Kind::Deployment;
  core::BoundedString<63> name;
};

/// Mix-in for components that switch deployments/configurations. The Configurator that creates
/// (or `attachClient`s) such a component connects it; until then requests are refused.
class ConfiguratorClient {
 public:
  /// Most requests waiting at once; more are refused (a chart asks once per state change).
  static constexpr std::size_t kQueueCapacity = 8;

  ConfiguratorClient() = default;
  virtual ~ConfiguratorClient() = default;
  ConfiguratorClient(const ConfiguratorClient&) = delete;
  ConfiguratorClient& operator=(const ConfiguratorClient&) = delete;

  /// Queues a switch. Real-time safe: no allocation, no lock. Returns false when no Configurator
  /// is attached, the queue is full, or `name` is longer than 63 characters.
  bool requestSwitch(SwitchRequest::Kind kind, std::string_view name) noexcept;
  /// True once a Configurator serves this client.
  bool attached() const noexcept { return configurator_.load(std::memory_order_acquire) != nullptr; }

 protected:
  /// The Configurator serving this client, or nullptr (e.g. to look up peers at configure time).
  Configurator* configurator() const noexcept { return configurator_.load(std::memory_order_acquire); }
  /// Called by the Configurator, between steps of every component, after carrying out
  /// `request`: `ok` false with the error in `message` when it failed (nothing changed then).
  virtual void onRequestDone(const SwitchRequest& request, bool ok, std::string_view message) = 0;

 private:
  friend class Configurator;
  /// Takes the oldest request (the Configurator's side). Returns false when there is none.
  bool takeRequest(SwitchRequest& out) noexcept;

  std::atomic<Configurator*> configurator_{nullptr};
  std::array<SwitchRequest, kQueueCapacity> queue_{};
  std::atomic<std::size_t> head_{0};  // next to take (Configurator)
  std::atomic<std::size_t> tail_{0};  // next to fill (client)
};

}  // namespace cobra::deploy
