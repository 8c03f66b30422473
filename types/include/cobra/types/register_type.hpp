#pragma once
/// @file
/// The one call that registers a data type with every capability of cobra (ARCHITECTURE §2):
/// @code
/// cobra::types::registerType<ProbeReading>();
/// @endcode
/// registers `T` in the core type registry (name, kind, text form, fields for the editor, studio
/// and console), for Lua (`cobra::script::LuaCodec<T>`: ports, properties and operation
/// arguments as Lua values), for the Reporter (`cobra::components::CsvCodec<T>`: CSV columns
/// with units, the studio's numeric series) and, in code built with the dds headers (a target
/// that uses cobra::dds), for DDS (`cobra::dds::registerDdsType<T>`). Each capability's codec is
/// found at compile time: a record (`DataTypeTraits<T> : RecordTraits<T>` with `fields`) has all
/// of them; any other type needs a specialisation of each codec, and a missing one fails to
/// compile with a message naming the codec to specialise (the instantiation trace names T).
///
/// DDS is the one capability not in every process: the `cobra` tool links neither Fast DDS nor
/// cobra::dds (its transport is the package cobra_dds, loaded RTLD_LOCAL), and cobra::types itself
/// is built without DDS. Whether registerType<T>() registers the DDS side is decided where it is
/// instantiated: `COBRA_TYPES_HAVE_DDS` is defined when `cobra/dds/register_type.hpp` is on the
/// include path. The two forms live in different inline namespaces, so a program whose
/// translation units differ in this still has one definition of each.
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
/// with cobra::dds in USES the package compiles the DDS side in and links the dds archives and
/// Fast DDS itself, and the `cobra` tool's transport, a package of its own, finds the type
/// through core::TypeFacets: dds/README.md. Without it the type gets no DDS wire.)

#include <typeindex>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/data_type.hpp"
#include "cobra/script/convert.hpp"
#if __has_include("cobra/dds/register_type.hpp")
#include "cobra/dds/register_type.hpp"
#define COBRA_TYPES_HAVE_DDS 1
#endif

namespace cobra::types {

#ifdef COBRA_TYPES_HAVE_DDS
inline namespace with_dds {
#else
inline namespace without_dds {
#endif

/// Registers `T` with the core registry and every capability registry of this build (DDS where
/// `COBRA_TYPES_HAVE_DDS`).
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

}  // inline namespace with_dds / without_dds

/// Registers cobra's own data types with the capabilities of every process (core, Lua, CSV):
/// core::BuiltinDataTypes (which the capability registries also add at their first use) and the
/// types defined above core, which only this call registers: TGL.MultiAxisPath and
/// Geometry.PointList with every capability, Imaging.GrayImage with core only (a port type: no
/// Lua or CSV form, see gray_image.hpp). The `cobra` tool
/// calls it at start-up, before a deployment is loaded (its run, studio and editor included); a
/// program of one's own that loads deployments calls it too. It registers nothing for DDS: the dds
/// transport seeds cobra's own types with their ROS 2 wires itself (dds::registerBuiltinWires,
/// from the same core::BuiltinDataTypes), wherever it is loaded.
void registerBuiltins();

/// True when `type` is registered for Lua and for CSV, the capabilities registerBuiltins() gives
/// every process. DDS is not checked: its registry is the dds transport's, in a package the tool
/// loads (dds::ddsTypes(), core::TypeFacets under "dds").
bool hasEveryCapability(const core::TypeInfo& type);

}  // namespace cobra::types
