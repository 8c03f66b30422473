#pragma once
/// @file
/// The types the dds transport carries: a runtime registry, filled once per type by whoever
/// owns the type, with `registerDdsType<T>()`. dds keeps no list of types: a port of a type
/// registered here can use `transport = "dds"`; another is refused when connected, naming the
/// type and this function.
/// @code
/// struct ProbeReading { double depth; KDL::Frame pose; };          // a record (core/record.hpp)
/// template <> struct cobra::core::DataTypeTraits<ProbeReading> : cobra::core::RecordTraits<ProbeReading> {
///   static constexpr std::string_view name = "us.ProbeReading";
///   static constexpr auto fields = std::tuple{cobra::core::field("depth", &ProbeReading::depth, "m"),
///                                             cobra::core::field("pose", &ProbeReading::pose, "m, quaternion")};
/// };
/// cobra::dds::registerDdsType<ProbeReading>();  // where the package registers its types
/// @endcode
/// The record then travels as `us::msg::dds_::ProbeReading_`, whose IDL `idlOf<ProbeReading>()`
/// gives (idl.hpp) for a ROS 2 node or another DDS program.
///
/// Registering is configure-time work (it allocates); it is thread-safe, and registering a type
/// again keeps the first registration. The transport looks a port's type up when a connection
/// is made.
///
/// A type registered by a package reaches the transport of the `cobra` tool although that
/// transport is a package of its own (libcobra_dds.so, loaded RTLD_LOCAL, with its own copy of
/// this registry): registerDdsType<T>() also publishes T's binding (a static of the registering
/// module) in the process-wide core::TypeFacets under the capability "dds", and the transport
/// looks there when its own registry has no entry for a port's type. The binding is a struct of
/// function pointers instantiated where T is registered, so both sides must be built from the
/// same cobra headers (the installed ones).

#include <string>
#include <string_view>
#include <typeindex>
#include <vector>

#include "cobra/core/data_type.hpp"
#include "cobra/core/type_facets.hpp"
#include "cobra/dds/codec.hpp"
#include "cobra/dds/detail/ends.hpp"

namespace cobra::dds {

namespace detail {
/// Adds `binding` for `type` unless it is there already.
void addBinding(std::type_index type, Binding binding);
/// The capability under which registerDdsType<T>() publishes T's binding in core::TypeFacets.
inline constexpr std::string_view facet = "dds";
/// The binding of `type`: this module's registry's, else the one a module published in
/// core::TypeFacets under `facet` (a package's type, when the transport is a package itself), or
/// nullptr. The pointer stays valid: bindings are never removed.
const Binding* findBinding(std::type_index type);
/// The cobra names of the registered types, comma-separated in registration order.
std::string registeredDdsTypes();
}  // namespace detail

/// Makes port type `T` usable by the dds transport. `T` is a registered cobra type
/// (core::DataTypeTraits<T>) with a DDS codec: a record, or a `DdsCodec<T>` specialisation
/// (codec.hpp); each missing piece is a compile error that says what to add.
template <class T>
void registerDdsType() {
  static_assert(core::RegisteredDataType<T>,
                "cobra: registerDdsType<T>() needs a registered cobra type: specialise cobra::core::DataTypeTraits<T> "
                "(a record: inherit cobra::core::RecordTraits<T> and list its fields)");
  static const detail::Binding binding = detail::binding<T>(std::string(core::typeInfo<T>().name));
  detail::addBinding(std::type_index(typeid(T)), binding);
  core::TypeFacets::set(std::type_index(typeid(T)), detail::facet, &binding);  // for other modules' transports
}

/// The cobra names of the types the dds transport carries, in registration order.
std::vector<std::string> ddsTypes();

/// The IDL of the registered record called `cobra_name` (idlOf), e.g. for `cobra_name`
/// "us.ProbeReading". @throws core::Error when no such type is registered, or when it is carried
/// by a message (its IDL is the message's, e.g. dds/idl/geometry_msgs/msg/Pose.idl for KDL.Frame).
std::string registeredIdl(std::string_view cobra_name);

/// Registers cobra's own types (core::BuiltinDataTypes, core's one list of them) with their
/// built-in ROS 2 wires. Every DdsTransport calls it when it is made; calling it again does
/// nothing.
void registerBuiltinWires();

}  // namespace cobra::dds
