#pragma once
/// @file
/// Reading and writing typed ports from Lua: the type-erased access a Lua port object holds.

#include <memory>

#include "cobra/core/port.hpp"

struct lua_State;

namespace cobra::script {

/// Type-erased access to one port. `read` pushes the flow status ("NoData", "OldData",
/// "NewData") and the value (nil on NoData) and returns 2; on an output port it reads through
/// a private data connection made at its first call (so it sees what is written after that).
/// `write` converts the Lua value at `index` and writes it (output ports only), returning 0.
/// Neither allocates from the system once made and the buffers have the data's size. Both
/// throw cobra::core::Error for misuse (wrong direction, wrong form); they raise no Lua error.
class PortAccess {
 public:
  explicit PortAccess(core::PortBase& port) : port_(&port) {}
  virtual ~PortAccess() = default;
  PortAccess(const PortAccess&) = delete;
  PortAccess& operator=(const PortAccess&) = delete;

  core::PortBase& port() const { return *port_; }
  virtual int read(lua_State* L) = 0;
  virtual int write(lua_State* L, int index) = 0;

 protected:
  [[noreturn]] void throwNotOutput() const;
  /// "NoData", "OldData", "NewData" as a Lua string (interned after the first push).
  static void pushStatus(lua_State* L, core::FlowStatus status);

 private:
  core::PortBase* port_;
};

/// Access through the type's text form, for types without a Conversion.
std::unique_ptr<PortAccess> makeTextPortAccess(core::PortBase& port);

}  // namespace cobra::script
