#pragma once
// `cobra new component`: writes a compilable component skeleton (header, source, unit test,
// CMake entry) into a package folder — the useful half of the thesis' OroEdit (§3.2.1).

#include <filesystem>
#include <string>
#include <vector>

namespace cobra::tools {

/// One port or property of the skeleton, from "name:Type[:unit]".
struct InterfaceItem {
  std::string name;
  std::string type;  ///< short type name: double, int, bool, string, vector, Frame, ...
  std::string unit;
};

struct ComponentTemplate {
  std::string name;     ///< C++ class and component type name, e.g. "VariableAdmittance"
  std::string role;     ///< calculation, supervision, decision or bridge
  std::string package;  ///< package (and include folder) name, e.g. "my_control"
  std::vector<InterfaceItem> inputs;
  std::vector<InterfaceItem> event_inputs;
  std::vector<InterfaceItem> outputs;
  std::vector<InterfaceItem> properties;
};

/// Parses "name:Type[:unit]". @throws std::runtime_error naming `what`, the text and the
/// accepted types.
InterfaceItem parseInterfaceItem(const std::string& text, const std::string& what);

/// Checks names (C++ identifiers, no duplicates) and role. @throws std::runtime_error.
void validate(const ComponentTemplate& t);

/// Writes the files into `folder` (created if needed) and returns their paths. An existing
/// file is never overwritten (error); the package CMakeLists.txt is created once and then
/// extended with one line per component.
std::vector<std::filesystem::path> generateComponent(const ComponentTemplate& t, const std::filesystem::path& folder);

}  // namespace cobra::tools
