#pragma once
/// @file
/// The component generator of `cobra new component` and of the editor's generate route
/// (studio/PROTOCOL.md): writes a compilable component skeleton (header, source, unit test) into
// a package folder built against an installed cobra (CMakeLists.txt with find_package(cobra) and
// cobra_add_package, src/package.cpp registering the components) — the useful half of the
// thesis' OroEdit (§3.2.1).

#include <filesystem>
#include <string>
#include <vector>

namespace cobra::core {
struct TypeInfo;
}

namespace cobra::studio {

/// True when the generator can write a port or property of `type`: the type has a C++ spelling
/// (core::TypeInfo::cpp). Every registered type, cobra's own and the loaded packages', is asked;
/// the editor's palette flags these (studio/PROTOCOL.md, data_types' "generate").
bool generatorKnows(const core::TypeInfo& type);
/// The names the generator accepts now (every type generatorKnows, by name, and by short name
/// when unambiguous), sorted, comma-separated: for help texts and error messages.
std::string generatorTypeNames();

/// One port or property of the skeleton, from "name:Type[:unit]".
struct InterfaceItem {
  std::string name;
  /// a registered data type with a C++ spelling (core::TypeInfo::cpp), by name ("KDL.Frame",
  /// "double", a loaded package's "my.Reading") or short name ("Frame", "vector")
  std::string type;
  std::string unit;
};

struct ComponentTemplate {
  std::string name;     ///< C++ class and component type name, e.g. "VariableAdmittance"
  std::string role;     ///< calculation, supervision, decision or bridge
  std::string package;  ///< package (and include folder) name, e.g. "my_control"
  /// One line saying what it does, with units (the class comment, the component's and the
  /// package registration's doc); "" leaves a line for the author to fill in.
  std::string doc;
  std::vector<InterfaceItem> inputs;
  std::vector<InterfaceItem> event_inputs;
  std::vector<InterfaceItem> outputs;
  std::vector<InterfaceItem> properties;
};

/// Parses "name:Type[:unit]". @throws std::runtime_error naming `what`, the text and the
/// accepted types.
InterfaceItem parseInterfaceItem(const std::string& text, const std::string& what);

/// Checks names (C++ identifiers, no duplicates), role and doc (one line). @throws std::runtime_error.
void validate(const ComponentTemplate& t);

/// Writes the files into `folder` (created if needed) and returns their paths. An existing
/// component file is never overwritten (error, before anything is written); the package's
/// CMakeLists.txt and src/package.cpp are created once, then extended for each component (a
/// line in CMakeLists.txt; an include and a registration at the marked lines of package.cpp).
std::vector<std::filesystem::path> generateComponent(const ComponentTemplate& t, const std::filesystem::path& folder);

}  // namespace cobra::studio
