#include "cobra/deploy/package_registry.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>

#include "cobra/deploy/install_layout.hpp"
#include "cobra/deploy/suggest.hpp"

namespace cobra::deploy {
namespace {

constexpr const char* kRegisterSymbol = "cobra_register_package";
constexpr const char* kAbiSymbol = "cobra_package_abi";

using RegisterFunction = void (*)(PackageBuilder&);
using AbiFunction = std::uint32_t (*)();

std::vector<std::filesystem::path> splitPath(const char* text) {
  std::vector<std::filesystem::path> out;
  if (text == nullptr) return out;
  std::string all(text);
  std::size_t begin = 0;
  while (begin <= all.size()) {
    const std::size_t end = std::min(all.find(':', begin), all.size());
    if (end > begin) out.emplace_back(all.substr(begin, end - begin));
    begin = end + 1;
  }
  return out;
}

std::string prefix(const SourceLocation& where) { return where.text() + ": "; }

}  // namespace

void PackageBuilder::addType(std::string type_name, std::string doc, ComponentFactory make) {
  if (registry_->staging_ == nullptr)
    throw core::Error("package '" + package_ + "': component types can only be added while the package loads");
  if (type_name.empty()) throw core::Error("package '" + package_ + "': a component type needs a non-empty name");
  if (const ComponentType* existing = registry_->findType(type_name))
    throw core::Error("package '" + package_ + "' registers component type '" + type_name +
                      "', which package '" + existing->package + "' already registered; type names must be unique");
  if (registry_->staging_->count(type_name) != 0)
    throw core::Error("package '" + package_ + "' registers component type '" + type_name + "' twice");
  registry_->staging_->emplace(type_name, ComponentType{type_name, std::move(doc), package_, std::move(make)});
}

PackageRegistry::PackageRegistry(std::vector<std::filesystem::path> search_path) : search_path_(std::move(search_path)) {
  for (auto& dir : splitPath(std::getenv("COBRA_PACKAGE_PATH"))) search_path_.push_back(std::move(dir));
  // Last: the packages installed beside an installed cobra tool (<prefix>/lib/cobra/packages).
  if (auto installed = installedPackageDirectory(); !installed.empty()) search_path_.push_back(std::move(installed));
}

void PackageRegistry::addBuiltin(std::string name, PackageRegistrar registrar) {
  if (builtins_.count(name) != 0) throw core::Error("a built-in package named '" + name + "' already exists");
  builtins_.emplace(std::move(name), std::move(registrar));
}

bool PackageRegistry::isLoaded(const std::string& name) const {
  return std::find(loaded_.begin(), loaded_.end(), name) != loaded_.end();
}

void PackageRegistry::registerWith(const std::string& name, const std::function<void(PackageBuilder&)>& registration,
                                   const SourceLocation& where) {
  std::map<std::string, ComponentType, std::less<>> staged;
  staging_ = &staged;
  try {
    PackageBuilder builder(*this, name);
    registration(builder);
  } catch (const std::exception& e) {
    staging_ = nullptr;
    throw core::Error(prefix(where) + "package '" + name + "' failed to register its components: " + e.what());
  }
  staging_ = nullptr;
  types_.merge(staged);
  loaded_.push_back(name);
}

void PackageRegistry::load(const std::string& name, const SourceLocation& where) {
  if (isLoaded(name)) return;
  if (auto builtin = builtins_.find(name); builtin != builtins_.end()) {
    registerWith(name, builtin->second, where);
    return;
  }
  const std::string file_name = "lib" + name + ".so";
  for (const auto& dir : search_path_) {
    const auto file = dir / file_name;
    std::error_code ignored;
    if (std::filesystem::is_regular_file(file, ignored)) {
      loadLibrary(name, file, where);
      return;
    }
  }
  std::string searched;
  for (const auto& dir : search_path_) searched += (searched.empty() ? "" : ":") + dir.string();
  throw core::Error(prefix(where) + "unknown package '" + name + "'" +
                    suggestionText(name, knownPackages(), "packages") + " (searched for " + file_name + " in " +
                    (searched.empty() ? std::string("no directory") : searched) +
                    "; add directories with COBRA_PACKAGE_PATH)");
}

void PackageRegistry::loadLibrary(const std::string& name, const std::filesystem::path& file,
                                  const SourceLocation& where) {
  // RTLD_NOW: a missing symbol is reported here, at deploy time, not at the first call.
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw core::Error(prefix(where) + "cannot load package '" + name + "' from " + file.string() + ": " + dlerror());
  // Never dlclose'd, even on failure below: static initialisers of the library have already run
  // and may have registered things (core data types) that point into it.
  auto* abi = reinterpret_cast<AbiFunction>(dlsym(handle, kAbiSymbol));
  if (abi == nullptr)
    throw core::Error(prefix(where) + "package '" + name + "' (" + file.string() + ") does not export " + kAbiSymbol +
                      "; define extern \"C\" std::uint32_t cobra_package_abi() returning "
                      "cobra::deploy::kPackageAbiVersion");
  if (const std::uint32_t version = abi(); version != kPackageAbiVersion)
    throw core::Error(prefix(where) + "package '" + name + "' (" + file.string() + ") was built for package ABI " +
                      std::to_string(version) + ", this cobra has ABI " + std::to_string(kPackageAbiVersion) +
                      "; rebuild the package against this cobra");
  auto* registration = reinterpret_cast<RegisterFunction>(dlsym(handle, kRegisterSymbol));
  if (registration == nullptr)
    throw core::Error(prefix(where) + "package '" + name + "' (" + file.string() + ") does not export " +
                      kRegisterSymbol + "; define extern \"C\" void cobra_register_package(cobra::deploy::PackageBuilder&)");
  registerWith(name, registration, where);
}

const ComponentType* PackageRegistry::findType(const std::string& type_name) const {
  const auto it = types_.find(type_name);
  return it == types_.end() ? nullptr : &it->second;
}

const ComponentType& PackageRegistry::type(const std::string& type_name, const SourceLocation& where) const {
  if (const ComponentType* found = findType(type_name)) return *found;
  std::string loaded;
  for (const auto& p : loaded_) loaded += (loaded.empty() ? "" : ", ") + p;
  throw core::Error(prefix(where) + "unknown component type '" + type_name + "'" +
                    suggestionText(type_name, typeNames(), "types") + " (loaded packages: " +
                    (loaded.empty() ? std::string("none") : loaded) + "; is its package in packages_list?)");
}

std::unique_ptr<core::Component> PackageRegistry::create(const std::string& type_name, const std::string& instance_name,
                                                         const SourceLocation& where) const {
  const ComponentType& found = type(type_name, where);
  try {
    auto component = found.make(instance_name);
    if (!component) throw core::Error("its factory returned no component");
    return component;
  } catch (const std::exception& e) {
    throw core::Error(prefix(where) + "cannot create '" + instance_name + "' of type '" + type_name + "': " + e.what());
  }
}

std::vector<std::string> PackageRegistry::typeNames() const {
  std::vector<std::string> out;
  for (const auto& [name, type] : types_) out.push_back(name);
  return out;
}

std::vector<std::string> PackageRegistry::knownPackages() const {
  std::vector<std::string> out;
  for (const auto& [name, registrar] : builtins_) out.push_back(name);
  for (const auto& dir : search_path_) {
    std::error_code error;
    for (std::filesystem::directory_iterator it(dir, error), end; !error && it != end; it.increment(error)) {
      const std::string file = it->path().filename().string();
      if (file.size() > 6 && file.starts_with("lib") && file.ends_with(".so"))
        out.push_back(file.substr(3, file.size() - 6));
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<std::string> PackageRegistry::loadedPackages() const { return loaded_; }

}  // namespace cobra::deploy
