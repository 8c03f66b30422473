#pragma once
/// @file
/// The run-time registry of Lua conversions: one `Conversion` per registered type, made from the
/// type's `LuaCodec<T>` (lua_codec.hpp, which lists the Lua forms) by `registerLuaType<T>()`.
///
/// cobra's own types (core::BuiltinDataTypes) are in the registry from its first use; a package's
/// type is added by `cobra::types::registerType<T>()` (or `registerLuaType<T>()` alone). Types
/// without a conversion travel as their text form (a Lua string, see `DataTypeTraits::print/parse`).

#include <any>
#include <memory>
#include <string>
#include <string_view>
#include <typeindex>
#include <utility>

#include "cobra/core/component.hpp"
#include "cobra/core/data_type.hpp"
#include "cobra/core/port.hpp"
#include "cobra/core/property.hpp"
#include "cobra/script/lua_codec.hpp"
#include "cobra/script/port_access.hpp"

struct lua_State;

namespace cobra::script {

/// How one registered type crosses the Lua boundary. Every function pointer is set.
struct Conversion {
  std::string_view type_name;  ///< TypeInfo::name
  std::string_view lua_form;   ///< the accepted Lua form, quoted in error messages
  /// Reads the Lua value at `index` into `out` (a value of the type). Raises no Lua error.
  /// @throws cobra::core::Error "expected <form>, got <what>" on a value of the wrong form.
  void (*read)(lua_State* L, int index, std::any& out);
  /// Pushes `value` (holding the type). A Lua memory error is caught and thrown as
  /// cobra::core::Error naming the pool; nothing else is thrown.
  void (*push)(lua_State* L, const std::any& value);
  /// The value of `property` (of this type) and setting it (Property::set: checked, applied
  /// between two updates).
  std::any (*get_property)(const core::PropertyBase& property);
  void (*set_property)(core::PropertyBase& property, const std::any& value);
  /// A reader/writer of `port` (of this type) that allocates nothing per call once made.
  std::unique_ptr<PortAccess> (*access)(core::PortBase& port);
  /// A new port or property of this type (for script-defined components).
  std::unique_ptr<core::PortBase> (*make_port)(core::PortDirection direction, std::string name, std::string doc,
                                               std::string unit);
  std::unique_ptr<core::PropertyBase> (*make_property)(std::string name, const std::any& initial, std::string unit,
                                                       std::string doc);
};

/// The conversion of `type`, or nullptr when it has none (use the text form then). Lock-free
/// and allocation-free: safe on a real-time thread.
const Conversion* findConversion(const core::TypeInfo& type);
/// By type name ("double", "KDL.Frame"), or nullptr.
const Conversion* findConversion(std::string_view type_name);
/// Names of every type with a conversion, comma-separated, in registration order (cobra's own
/// first; for error messages).
std::string conversionNames();

/// Adds the conversion of the type `id`; adding the same type again does nothing.
/// @throws core::Error when another type has the same name, or the registry is full (256 types).
void addConversion(std::type_index id, const Conversion& conversion);

/// "the number 1.5", "a table", "the string \"abc\"": what a Lua value is, for messages.
std::string describeLuaValue(lua_State* L, int index);

// ---- The generic parts of a conversion, instantiated once per type ---------------------------

namespace convert_detail {

template <class T>
void pushErased(lua_State* L, const void* value) {
  LuaCodec<T>::push(L, *static_cast<const T*>(value));
}

/// Pushes `value`; numbers and booleans directly (no allocation), the rest in protected mode.
template <class T>
void pushValue(lua_State* L, const T& value) {
  if constexpr (std::is_arithmetic_v<T>) LuaCodec<T>::push(L, value);
  else lua_codec::pushProtected(L, &pushErased<T>, &value);
}

template <class T>
void readAny(lua_State* L, int index, std::any& out) {
  index = lua_codec::absIndex(L, index);  // the codecs push while reading
  T value{};
  LuaCodec<T>::read(L, index, value);
  out = std::move(value);
}

template <class T>
void pushAny(lua_State* L, const std::any& value) {
  pushValue(L, std::any_cast<const T&>(value));
}

template <class T>
core::Property<T>& typed(core::PropertyBase& property) {
  auto* p = dynamic_cast<core::Property<T>*>(&property);
  if (p == nullptr) throw core::Error(property.where() + " is not a " + std::string(core::DataTypeTraits<T>::name));
  return *p;
}

/// True on the activity thread of the property's owner.
bool onOwnersThread(const core::PropertyBase& property);

template <class T>
std::any getProperty(const core::PropertyBase& property) {
  const core::Property<T>& p = typed<T>(const_cast<core::PropertyBase&>(property));
  // On the owner's activity thread (a hook reading its own property) changes are applied on
  // this very thread between steps: read without the lock, which could block real-time code.
  if (onOwnersThread(property)) return p.get();
  return p.value();
}

template <class T>
void setProperty(core::PropertyBase& property, const std::any& value) {
  typed<T>(property).set(std::any_cast<const T&>(value));
}

/// The message of a refused port write (allocates; only on the error path).
[[noreturn]] void refuseWrite(const core::PortBase& port, const core::Error& e);

/// Port access with preallocated buffers: read/write copy into them, never allocate once they
/// have the data's size.
template <class T>
class TypedPortAccess final : public PortAccess {
 public:
  explicit TypedPortAccess(core::PortBase& port)
      : PortAccess(port),
        input_(dynamic_cast<core::InputPort<T>*>(&port)),
        output_(dynamic_cast<core::OutputPort<T>*>(&port)) {}

  int read(lua_State* L) override {
    core::InputPort<T>* input = input_;
    if (input == nullptr) {
      // An output port (read from a console): through a private data connection made at the
      // first read, so that read sees only what is written after it.
      if (!reader_) {
        auto reader = std::make_unique<core::InputPort<T>>("lua_reader_" + port().name(),
                                                           "Lua reader of " + port().fullName(), port().unit());
        output_->connectTo(*reader, core::ConnPolicy::data());
        reader_ = std::move(reader);
      }
      input = reader_.get();
    }
    const core::FlowStatus status = input->read(read_buffer_);
    pushStatus(L, status);
    if (status == core::FlowStatus::NoData) lua_codec::pushNil(L);
    else pushValue(L, read_buffer_);
    return 2;
  }

  int write(lua_State* L, int index) override {
    if (output_ == nullptr) throwNotOutput();
    try {
      LuaCodec<T>::read(L, index, write_buffer_);
    } catch (const core::Error& e) {
      refuseWrite(port(), e);
    }
    output_->write(write_buffer_);
    return 0;
  }

 private:
  core::InputPort<T>* input_;
  core::OutputPort<T>* output_;
  std::unique_ptr<core::InputPort<T>> reader_;  // reads an output port; declared after output_
  T read_buffer_{};
  T write_buffer_{};
};

template <class T>
std::unique_ptr<PortAccess> makeAccess(core::PortBase& port) {
  return std::make_unique<TypedPortAccess<T>>(port);
}

template <class T>
std::unique_ptr<core::PortBase> makePort(core::PortDirection direction, std::string name, std::string doc,
                                         std::string unit) {
  if (direction == core::PortDirection::Input)
    return std::make_unique<core::InputPort<T>>(std::move(name), std::move(doc), std::move(unit));
  return std::make_unique<core::OutputPort<T>>(std::move(name), std::move(doc), std::move(unit));
}

template <class T>
std::unique_ptr<core::PropertyBase> makeProperty(std::string name, const std::any& initial, std::string unit,
                                                 std::string doc) {
  return std::make_unique<core::Property<T>>(std::move(name), std::any_cast<const T&>(initial), std::move(unit),
                                             std::move(doc));
}

}  // namespace convert_detail

/// The conversion of `T`, made from `LuaCodec<T>` (a compile error names T when it has none).
template <class T>
Conversion conversionOf() {
  using namespace convert_detail;
  return {core::typeInfo<T>().name, LuaCodec<T>::form(), &readAny<T>, &pushAny<T>, &getProperty<T>,
          &setProperty<T>, &makeAccess<T>, &makePort<T>, &makeProperty<T>};
}

/// Registers `T` (and its TypeInfo) for Lua: ports, properties and operation arguments of type T
/// are then read and written as Lua values of `LuaCodec<T>`'s form. Idempotent.
template <class T>
void registerLuaType() {
  addConversion(std::type_index(typeid(T)), conversionOf<T>());
}

}  // namespace cobra::script
