#pragma once
// The editor's parts (internal to cobra::studio): the palette, the Project JSON and its
// conversion to and from deploy::DeploymentDescription, and the checks (studio/PROTOCOL.md).

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cobra/core/introspection.hpp"
#include "cobra/deploy/description.hpp"
#include "cobra/deploy/package_registry.hpp"
#include "cobra/studio/editor.hpp"
#include "cobra/studio/json.hpp"

namespace cobra::studio::editor {

/// A request or project that cannot be used: HTTP `status` (400, 404, 409, 422) and the text.
struct Refusal : std::runtime_error {
  Refusal(int s, const std::string& what) : std::runtime_error(what), status(s) {}
  int status;
};

struct PaletteType {
  std::string type, package, doc;
  core::ComponentInfo info;  ///< a component of the type, made once: ports, properties, operations
  const core::PortInfo* port(const std::string& name) const;
  const core::PropertyInfo* property(const std::string& name) const;
  std::vector<std::string> portNames() const;
  std::vector<std::string> propertyNames() const;
};

/// Every component type of every package cobra can load, from the runtime's introspection.
class Palette {
 public:
  /// Loads every package `packages` knows (cobra's built-in ones added here) and makes one
  /// component of each type.
  explicit Palette(std::unique_ptr<deploy::PackageRegistry> packages);
  const PaletteType* find(const std::string& type) const;
  /// @throws Refusal 422 "component 'X': unknown component type 'T'; did you mean ...".
  const PaletteType& get(const std::string& component, const std::string& type) const;
  /// A component of `type` named `name`, to check property text and lint connections with.
  std::unique_ptr<core::Component> make(const std::string& type, const std::string& name) const;
  /// A component of `type` named `name` with the property values `values` (name, text) set and,
  /// unless it is a bridge, configured: the ports a component makes when it configures (a
  /// trajectory generator's desCartPose_i, one per arm) exist then. A bridge is not configured
  /// (it may reach for its device); neither is a component whose configure fails (its ports as
  /// made). @throws what setting a value throws (its text is checked first by `validate`).
  std::unique_ptr<core::Component> makeConfigured(const std::string& type, const std::string& name,
                                                  const std::vector<std::pair<std::string, std::string>>& values) const;
  std::string json() const;
  std::vector<std::string> typeNames() const;

 private:
  std::unique_ptr<deploy::PackageRegistry> packages_;
  std::vector<std::string> known_packages_;
  std::vector<std::string> errors_;  // packages that did not load, with why
  std::map<std::string, PaletteType, std::less<>> types_;
};

/// Component positions of the layout sidecar, by component name (px).
using Layout = std::map<std::string, std::pair<double, double>, std::less<>>;

/// The Project JSON of `d` with block positions from `layout` (absent: a grid).
std::string projectJson(const deploy::DeploymentDescription& d, const Layout& layout);
/// The description a Project holds; property values equal to the type's default are left out
/// (the file `cobra describe` would write). Its layout goes to `layout`.
/// @throws Refusal 422 naming the member that is missing or of the wrong kind.
deploy::DeploymentDescription fromProjectJson(const json::Json& project, const Palette& palette, Layout& layout);
std::string layoutJson(const Layout& layout);
/// The `now` member of GET /api/editor/running: `{ "t", "switches", "deployments": [ { "scope",
/// "deployment" } ], "configuration", "running": [names], "connections": [Connection] }`.
std::string inForceJson(const InForce& now);
Layout parseLayout(const std::string& text);

/// "A.x", "B.y" and a policy, as a ConnectionSpec (the `connection` member of check).
deploy::ConnectionSpec connectionFrom(const json::Json& connection, const std::string& where);

struct LintItem {
  std::string rule, message;
};
struct ConnectionVerdict {
  std::string reason;  ///< "" when the connection can be made
  std::vector<LintItem> lint;
};
/// Checks one connection of `d`: ports exist (did you mean), output to input, same type, policy;
/// then the role linter's verdict.
ConnectionVerdict checkConnection(const deploy::DeploymentDescription& d, const deploy::ConnectionSpec& c,
                                  const Palette& palette);

struct Problem {
  std::string where, message;
};
/// Every problem of `d` (property text against type and range, activities, peers, connections,
/// deployments, configurations) and the linter's verdicts on its connections.
std::vector<Problem> validate(const deploy::DeploymentDescription& d, const Palette& palette, std::vector<LintItem>& lint);

std::string lintJson(const std::vector<LintItem>& lint);

}  // namespace cobra::studio::editor
