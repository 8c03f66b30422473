#pragma once
/// @file
/// Named deployments and named configurations (thesis §2.2.1–2.2.3): each state of a task asks
/// for one deployment (which components run, with which activity, wired how) and one
/// configuration (property values per component); the Configurator switches between them at
/// run time.

#include <filesystem>
#include <istream>
#include <map>
#include <string>
#include <vector>

#include "cobra/deploy/spec.hpp"

namespace cobra::deploy {

/// A named deployment: the components it runs (started in this order), their activities and
/// the connections between them. Components are instances made by `initConfigurator`.
struct DeploymentSpec {
  std::string name;
  SourceLocation where;
  std::vector<NameEntry> components;
  std::vector<ActivitySpec> activities;  ///< components without an entry keep their activity
  std::vector<ConnectionSpec> connections;
  /// The switch group this deployment belongs to ("" is the default one). Deployments of different
  /// scopes switch independently — e.g. one scope per robot, so the needle robot can go to
  /// teleoperation while the probe robot keeps its deployment. A component or a connection belongs
  /// to the deployments of one scope only.
  std::string scope{};
};

/// One property value of a configuration, as text in the property type's text form
/// (e.g. "2.5", "[0, 0.5, 1.2]", "true").
struct PropertyValueSpec {
  std::string component;
  std::string property;
  std::string value;
  SourceLocation where;
};

/// A named configuration: property values per component.
struct ConfigurationSpec {
  std::string name;
  SourceLocation where;
  std::vector<PropertyValueSpec> values;
};

/// The deployments and configurations a Configurator can switch between, by name.
class DeploymentSet {
 public:
  /// @throws core::Error naming both locations when a deployment of that name exists.
  void addDeployment(DeploymentSpec deployment);
  /// @throws core::Error naming both locations when a configuration of that name exists.
  void addConfiguration(ConfigurationSpec configuration);

  const DeploymentSpec* findDeployment(const std::string& name) const;
  const ConfigurationSpec* findConfiguration(const std::string& name) const;
  /// @throws core::Error "no deployment named 'x'; did you mean ...? known deployments: ...".
  const DeploymentSpec& deployment(const std::string& name) const;
  const ConfigurationSpec& configuration(const std::string& name) const;

  std::vector<std::string> deploymentNames() const;
  std::vector<std::string> configurationNames() const;

 private:
  std::map<std::string, DeploymentSpec, std::less<>> deployments_;
  std::map<std::string, ConfigurationSpec, std::less<>> configurations_;
};

/// Reads a configuration file in the plain-text form, one value per line:
/// @code
/// # comment
/// Gain.k = 2.5
/// Sine.frequency = 50
/// @endcode
/// The configuration is named after the file's stem ("slow.cfg" -> "slow"); each value's
/// location is the file and line it is on.
/// @throws core::Error "file:line: ..." on a line that is not `Component.property = value`.
ConfigurationSpec loadConfigurationFile(const std::filesystem::path& file);

/// The parser behind loadConfigurationFile: reads `in` as configuration `name`, naming
/// `file` in locations and errors.
ConfigurationSpec parseConfiguration(std::istream& in, const std::string& name, const std::string& file);

/// Every `*.cfg` file of `folder`, in name order.
/// @throws core::Error when the folder does not exist or a file is malformed.
std::vector<ConfigurationSpec> loadConfigurationFolder(const std::filesystem::path& folder);

}  // namespace cobra::deploy
