#pragma once
/// @file
/// The one call that registers a data type with every capability of cobra (ARCHITECTURE §2):
/// @code
/// cobra::types::registerType<ProbeReading>();
/// @endcode
/// registers `T` in the core type registry (name, kind, text form, fields for the editor, studio
/// and console), for Lua (`cobra::script::LuaCodec<T>`: ports, properties and operation
/// arguments as Lua values), for the Reporter (`cobra::components::CsvCodec<T>`: CSV columns
/// with units, the studio's numeric series) and for DDS (`cobra::dds::registerDdsType<T>`) when
/// that module is present. Each capability's codec is found at compile time: a record
/// (`DataTypeTraits<T> : RecordTraits<T>` with `fields`) has all of them; any other type needs a
/// specialisation of each codec, and a missing one fails to compile with a message naming the
/// codec to specialise (the instantiation trace names T).
///
/// Registering is idempotent and thread-safe; do it at start-up, not on a real-time thread. A
/// package registers its types in its entry point, next to its components:
/// @code
/// extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
///   cobra::types::registerType<us::ProbeReading>();
///   package.component<us::ProbeMonitor>("ProbeMonitor", "...");
/// }
/// @endcode
/// (cobra_add_package(... USES cobra::types cobra::script cobra::components::reporting cobra::dds);
/// with cobra::dds the package carries the dds side itself, and the `cobra` tool's transport, a
/// package of its own, finds the type through core::TypeFacets: dds/README.md).

#include <typeindex>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/data_type.hpp"
#include "cobra/script/convert.hpp"
#if __has_include("cobra/dds/register_type.hpp")
#include "cobra/dds/register_type.hpp"
#define COBRA_TYPES_HAVE_DDS 1
#endif

namespace cobra::types {

/// Registers `T` with the core registry and every capability registry.
template <class T>
void registerType() {
  static_assert(core::RegisteredDataType<T>,
                "cobra: registerType<T>: T is not a registered data type; specialise cobra::core::DataTypeTraits<T> "
                "(a record: DataTypeTraits<T> : RecordTraits<T> with name and fields)");
  (void)core::typeInfo<T>();
  script::registerLuaType<T>();
  components::registerCsvType<T>();
#ifdef COBRA_TYPES_HAVE_DDS
  dds::registerDdsType<T>();
#endif
}

/// Registers cobra's own data types with every capability: core::BuiltinDataTypes (which the
/// capability registries also add at their first use) and the types defined above core
/// (TGL.MultiAxisPath), which only this call registers. The `cobra` tool calls it at start-up,
/// before a deployment is loaded (its run, studio and editor included); a program of one's own
/// that loads deployments calls it too.
void registerBuiltins();

/// True when `type` is registered for Lua, for CSV (and for DDS when present).
bool hasEveryCapability(const core::TypeInfo& type);

}  // namespace cobra::types
