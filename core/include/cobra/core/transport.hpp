#pragma once
/// @file
/// Transports: connections whose samples travel through something other than this process's
/// memory (another process, another host), chosen per connection by `ConnPolicy::transport`.
///
/// Core knows no transport; a library registers one by name (cobra_dds registers "dds") and
/// `connectPorts` uses it when a policy names it. A transport makes the two *ends* of a
/// connection: the writer's end takes what an output port writes, the reader's end feeds an
/// input port. Both are ordinary channels to a port the end owns, so port code, the data/buffer
/// semantics and the flow status stay those of local connections, and the real-time side of a
/// port never sees the transport:
/// - writer's end: `output` -> [channel with the connection's policy] -> a hidden input port that
///   the transport's own thread drains and sends;
/// - reader's end: a hidden output port that the transport's receiving thread writes ->
///   [channel with the connection's policy] -> `input`.
/// An end lives as long as that channel: disconnecting the port (or destroying it) ends it.
///
/// Configure-time only: every function here may allocate and lock.

#include <memory>
#include <string>
#include <vector>

#include "cobra/core/conn_policy.hpp"

namespace cobra::core {

class PortBase;
class OutputPortBase;
class InputPortBase;

/// A transport's state for one end of a connection, held by the end's channel.
class TransportEnd {
 public:
  virtual ~TransportEnd() = default;
  /// Stops every thread of the transport that uses the end's hidden port; called before the
  /// channel is removed from its ports (then the end is destroyed with the channel). Blocks
  /// until those threads let go; configure-time only.
  virtual void close() noexcept = 0;
};

/// A named way to carry connections between processes. Implementations are thread-safe.
class Transport {
 public:
  virtual ~Transport() = default;

  /// Checks the parts of `policy` the transport reads (`topic`, `options`).
  /// @throws Error naming the bad option key or value and what is allowed (no location: the
  /// caller prefixes its own, e.g. a deployment file's file:line).
  virtual void check(const ConnPolicy& policy) const = 0;

  /// Makes the end that sends what `output` writes. Attach it with `attachTransportEnd`.
  /// @throws Error when `output`'s type has no representation on this transport, or the
  /// transport refuses the policy.
  virtual void makeWriterEnd(OutputPortBase& output, const ConnPolicy& policy, PortBase* peer) = 0;
  /// Makes the end that feeds `input` with what arrives. @throws as makeWriterEnd.
  virtual void makeReaderEnd(InputPortBase& input, const ConnPolicy& policy, PortBase* peer) = 0;
};

/// Connects `port` to `hidden` (the end's own port, of the opposite direction and the same type)
/// with `policy`, and ties `end` (the transport's state for this end) to that channel, so that
/// it lives until the channel is removed. `peer`: the port at the connection's far end when it
/// is in this process (both ends made by one `connectPorts`), so that `connectedTo` and
/// `disconnectPorts` see the connection; nullptr otherwise.
void attachTransportEnd(PortBase& port, PortBase& hidden, const ConnPolicy& policy,
                        std::shared_ptr<TransportEnd> end, PortBase* peer);

/// The process's transports, by name.
class TransportRegistry {
 public:
  /// Adds `transport` as `name` (letters, digits, '_', '-'). Adding a name again from the same
  /// `owner` replaces it. @throws Error when the name is malformed or another owner has it.
  static void add(const std::string& name, const std::string& doc, const std::string& owner,
                  std::shared_ptr<Transport> transport);
  /// Removes `name` (connections it made keep their ends). Returns false when it was not there.
  static bool remove(const std::string& name);
  /// The transport called `name`. @throws Error "unknown transport 'x'; transports: ..." listing
  /// the registered ones.
  static std::shared_ptr<Transport> get(const std::string& name);
  /// Registered names, sorted.
  static std::vector<std::string> names();
};

/// Connects `port` alone to `policy.transport`: the writer's end for an output port, the
/// reader's end for an input port; the other end is in another process (or made by another
/// call). @throws Error naming the port when the policy names no transport or the transport
/// refuses.
void connectToTransport(PortBase& port, const ConnPolicy& policy);

}  // namespace cobra::core
