#pragma once
/// @file
/// Per-type capabilities shared by every module of a process: a facet is a pointer to whatever a
/// capability needs for one data type (e.g. the DDS transport's binding, "dds"), published under
/// (type, capability) by the code that registers the type and found by the module that uses it.
///
/// Why in core: core exists once per process (the `cobra` tool exports it to the packages it
/// loads), while a module may exist several times: the dds transport is a package of its own
/// (libcobra_dds.so, loaded RTLD_LOCAL) with its own copy of the dds objects and so its own dds
/// registry. A user package that registers its type publishes the facet here; the transport
/// finds it here when its own registry has no entry.
/// @code
/// static const MyBinding binding = makeBinding<T>();      // lives as long as the process
/// cobra::core::TypeFacets::set(typeid(T), "dds", &binding);  // at registration (start-up)
/// auto* b = static_cast<const MyBinding*>(cobra::core::TypeFacets::get(typeid(T), "dds"));
/// @endcode
///
/// set() is configure-time work: it takes a lock and may allocate; a second set() of the same
/// (type, capability) keeps the first facet. get() is lock-free and never allocates (it may run
/// on a real-time thread): the facets are an append-only array of at most `capacity` entries,
/// each published with a release store. The facet pointed to must outlive every get() (a
/// static, or an object of a package that is never unloaded: cobra never unloads packages).

#include <cstddef>
#include <string_view>
#include <typeindex>

namespace cobra::core {

class TypeFacets {
 public:
  /// The most facets a process holds (types × capabilities).
  static constexpr std::size_t capacity = 1024;
  /// The longest capability name (longer names are refused).
  static constexpr std::size_t max_capability = 31;

  /// Publishes `facet` (not null) for (`type`, `capability`). Returns true when published, false
  /// when that pair has a facet already (the first one is kept).
  /// @throws core::Error when `facet` is null, `capability` is empty or longer than
  /// max_capability, or the table is full.
  static bool set(std::type_index type, std::string_view capability, const void* facet);

  /// The facet of (`type`, `capability`), or nullptr. Lock-free, allocation-free.
  static const void* get(std::type_index type, std::string_view capability) noexcept;

  /// How many facets are published.
  static std::size_t size() noexcept;
};

}  // namespace cobra::core
