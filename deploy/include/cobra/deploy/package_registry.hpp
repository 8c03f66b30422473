#pragma once
/// @file
/// Component types and the packages that provide them: built-in packages registered from C++,
/// and shared-library packages loaded by name with dlopen.
///
/// A shared-library package `foo` is a file `libfoo.so` on the search path that exports:
/// @code
/// extern "C" std::uint32_t cobra_package_abi() { return cobra::deploy::kPackageAbiVersion; }
/// extern "C" void cobra_register_package(cobra::deploy::PackageBuilder& package) {
///   package.component<MyFilter>("MyFilter", "low-pass filter of a wrench");
/// }
/// @endcode
/// Build it with `cobra_add_package()` (cmake/CobraPackage.cmake; `find_package(cobra)` outside
/// cobra's tree): a CMake `MODULE` library without cobra linked into it. It uses the cobra of the
/// process that loads it, which must hold the cobra code the package calls and export its
/// symbols: the `cobra` tool does, for every cobra library (`cobra_link_package_host()`), so
/// registries exist once. A package built against another `kPackageAbiVersion` is
/// refused at load. Loaded libraries are never unloaded: components and factories made by
/// them may live until the process ends.

#include <concepts>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "cobra/core/backend_registry.hpp"
#include "cobra/core/component.hpp"
#include "cobra/deploy/spec.hpp"

namespace cobra::deploy {

/// Version of the interface between cobra and shared-library packages (PackageBuilder and the
/// core classes components derive from). Raised whenever that interface changes incompatibly.
inline constexpr std::uint32_t kPackageAbiVersion = 2;

/// Makes a component of one type, named `name`.
using ComponentFactory = std::function<std::unique_ptr<core::Component>(const std::string& name)>;

/// A creatable component type.
struct ComponentType {
  std::string name;     ///< type name used in `components_list`, e.g. "Gain"
  std::string doc;      ///< one line for listings
  std::string package;  ///< the package that registered it
  ComponentFactory make;
};

class PackageRegistry;

/// What a package's registration function receives: registers the package's component types.
class PackageBuilder {
 public:
  PackageBuilder(PackageRegistry& registry, std::string package) : registry_(&registry), package_(std::move(package)) {}

  /// Registers component type `T` as `type_name`. T must derive from core::Component and be
  /// constructible from its instance name.
  /// @throws core::Error when `type_name` is already registered (by this or another package).
  template <class T>
  PackageBuilder& component(std::string type_name, std::string doc) {
    static_assert(std::is_base_of_v<core::Component, T>,
                  "cobra: PackageBuilder::component<T>: T must derive from cobra::core::Component");
    static_assert(std::is_constructible_v<T, std::string>,
                  "cobra: PackageBuilder::component<T>: T needs a constructor taking its instance name "
                  "(explicit T(std::string name))");
    addType(std::move(type_name), std::move(doc),
            [](const std::string& name) -> std::unique_ptr<core::Component> { return std::make_unique<T>(name); });
    return *this;
  }

  /// Registers the backend scheme `scheme` of device interface `I` (core::BackendRegistry<I>):
  /// a driver whose `bus` or `device` property is `<scheme>:<address>` gets `make(address)`.
  /// Registered for the process; loading the package again replaces its own schemes.
  /// @throws core::Error when another package registered `scheme` for `I`.
  template <class I, class F>
  PackageBuilder& backend(const std::string& scheme, const std::string& doc, F make) {
    static_assert(std::is_invocable_r_v<std::unique_ptr<I>, F, const std::string&>,
                  "cobra: PackageBuilder::backend<I>(scheme, doc, make): make must be callable as "
                  "std::unique_ptr<I>(const std::string& address)");
    core::BackendRegistry<I>::addFactory(scheme, doc, "package '" + package_ + "'", std::move(make));
    return *this;
  }

  const std::string& packageName() const { return package_; }

 private:
  void addType(std::string type_name, std::string doc, ComponentFactory make);
  PackageRegistry* registry_;
  std::string package_;
};

/// The registration function of a built-in package.
using PackageRegistrar = std::function<void(PackageBuilder&)>;

/// Known packages (built-in and found on the search path), loaded packages and their component
/// types. Used from one thread (the deployer).
class PackageRegistry {
 public:
  /// @param search_path directories searched for `lib<name>.so`, before those of the
  ///        environment variable COBRA_PACKAGE_PATH (colon-separated).
  ///        Then the installed packages' folder beside an installed tool
  ///        (installedPackageDirectory(), `<prefix>/lib/cobra/packages`), when it exists.
  /// No package is built in here: cobra's own are added by components::addBuiltinPackages
  /// (components/builtin_packages), a program's own with addBuiltin.
  explicit PackageRegistry(std::vector<std::filesystem::path> search_path = {});

  /// Makes `name` loadable without a shared library. @throws core::Error on a duplicate name.
  void addBuiltin(std::string name, PackageRegistrar registrar);

  /// Loads package `name` (a built-in one, or `lib<name>.so` from the search path); loading a
  /// loaded package again does nothing.
  /// @throws core::Error prefixed with `where`: unknown package (with the closest names),
  ///         a library that cannot be opened, lacks the entry points, has another ABI version,
  ///         or registers a type name that exists already. A failed load registers nothing.
  void load(const std::string& name, const SourceLocation& where = {});
  bool isLoaded(const std::string& name) const;

  /// The type called `type_name`, or nullptr when no loaded package registered it.
  const ComponentType* findType(const std::string& type_name) const;
  /// @throws core::Error prefixed with `where`: "unknown component type 'Gian'; did you mean
  ///         'Gain'? known types: ...".
  const ComponentType& type(const std::string& type_name, const SourceLocation& where = {}) const;
  /// Creates a component of type `type_name` named `instance_name`.
  /// @throws core::Error prefixed with `where` (unknown type, or the constructor threw).
  std::unique_ptr<core::Component> create(const std::string& type_name, const std::string& instance_name,
                                          const SourceLocation& where = {}) const;

  /// Names of the registered component types, sorted.
  std::vector<std::string> typeNames() const;
  /// Names of the known packages: built-in ones and `lib<name>.so` files on the search path.
  std::vector<std::string> knownPackages() const;
  std::vector<std::string> loadedPackages() const;
  const std::vector<std::filesystem::path>& searchPath() const { return search_path_; }

 private:
  friend class PackageBuilder;
  void loadLibrary(const std::string& name, const std::filesystem::path& file, const SourceLocation& where);
  void registerWith(const std::string& name, const std::function<void(PackageBuilder&)>& registration,
                    const SourceLocation& where);

  std::vector<std::filesystem::path> search_path_;
  std::map<std::string, PackageRegistrar, std::less<>> builtins_;
  std::vector<std::string> loaded_;
  std::map<std::string, ComponentType, std::less<>> types_;
  // Types added by the registration in progress; moved into types_ only when it succeeds.
  std::map<std::string, ComponentType, std::less<>>* staging_ = nullptr;
};

}  // namespace cobra::deploy
