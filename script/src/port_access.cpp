#include "cobra/script/port_access.hpp"

#include <string>

#include "cobra/core/error.hpp"
#include "lua_guard.hpp"

namespace cobra::script {

void PortAccess::throwNotOutput() const {
  throw core::Error("port " + port_->fullName() + " is an input port: only output ports can be written");
}

void PortAccess::pushStatus(lua_State* L, core::FlowStatus status) {
  static constexpr const char* kNames[] = {"NoData", "OldData", "NewData"};
  detail::pushString(L, kNames[static_cast<int>(status)]);
}

namespace {

/// Through the type's text form: allocates (formats and parses text); for types without a
/// Conversion, which have no real-time Lua path.
class TextPortAccess final : public PortAccess {
 public:
  using PortAccess::PortAccess;

  int read(lua_State* L) override {
    auto* input = dynamic_cast<core::InputPortBase*>(&port());
    if (input == nullptr) {  // an output port: see TypedPortAccess::read
      if (!reader_) {
        auto& output = dynamic_cast<core::OutputPortBase&>(port());
        auto reader = output.makeReader("lua_reader_" + port().name(), "Lua reader of " + port().fullName());
        output.connectTo(*reader, core::ConnPolicy::data());
        reader_ = std::move(reader);
      }
      input = reader_.get();
    }
    std::string text;
    const core::FlowStatus status = input->readText(text);
    pushStatus(L, status);
    if (status == core::FlowStatus::NoData) lua_pushnil(L);
    else detail::pushString(L, text);
    return 2;
  }

  int write(lua_State* L, int index) override {
    auto* output = dynamic_cast<core::OutputPortBase*>(&port());
    if (output == nullptr) throwNotOutput();
    if (lua_type(L, index) != LUA_TSTRING)
      throw core::Error("port " + port().fullName() + " is a " + std::string(port().type().name) +
                        ", which Lua writes as text: expected a string (" + std::string(port().type().format) + ")");
    std::size_t n = 0;
    const char* s = lua_tolstring(L, index, &n);
    output->writeText(std::string_view(s, n));
    return 0;
  }

 private:
  std::unique_ptr<core::InputPortBase> reader_;
};

}  // namespace

std::unique_ptr<PortAccess> makeTextPortAccess(core::PortBase& port) { return std::make_unique<TextPortAccess>(port); }

}  // namespace cobra::script
