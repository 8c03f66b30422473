#include "cobra/deploy/deployment_set.hpp"

#include <algorithm>
#include <fstream>

#include "cobra/core/error.hpp"
#include "cobra/deploy/suggest.hpp"
#include "cobra/text/trim.hpp"

namespace cobra::deploy {
namespace {

template <class Map>
std::vector<std::string> keysOf(const Map& map) {
  std::vector<std::string> out;
  for (const auto& [name, value] : map) out.push_back(name);
  return out;
}

std::string trim(std::string_view line) { return std::string(cobra::text::trim(line)); }

}  // namespace

void DeploymentSet::addDeployment(DeploymentSpec deployment) {
  if (const auto it = deployments_.find(deployment.name); it != deployments_.end())
    throw core::Error(deployment.where.text() + ": a deployment named '" + deployment.name + "' already exists (" +
                      it->second.where.text() + "); give each deployment its own name");
  std::string name = deployment.name;
  deployments_.emplace(std::move(name), std::move(deployment));
}

void DeploymentSet::addConfiguration(ConfigurationSpec configuration) {
  if (const auto it = configurations_.find(configuration.name); it != configurations_.end())
    throw core::Error(configuration.where.text() + ": a configuration named '" + configuration.name +
                      "' already exists (" + it->second.where.text() + "); give each configuration its own name");
  std::string name = configuration.name;
  configurations_.emplace(std::move(name), std::move(configuration));
}

const DeploymentSpec* DeploymentSet::findDeployment(const std::string& name) const {
  const auto it = deployments_.find(name);
  return it == deployments_.end() ? nullptr : &it->second;
}

const ConfigurationSpec* DeploymentSet::findConfiguration(const std::string& name) const {
  const auto it = configurations_.find(name);
  return it == configurations_.end() ? nullptr : &it->second;
}

const DeploymentSpec& DeploymentSet::deployment(const std::string& name) const {
  if (const DeploymentSpec* found = findDeployment(name)) return *found;
  throw core::Error("no deployment named '" + name + "'" + suggestionText(name, deploymentNames(), "deployments"));
}

const ConfigurationSpec& DeploymentSet::configuration(const std::string& name) const {
  if (const ConfigurationSpec* found = findConfiguration(name)) return *found;
  throw core::Error("no configuration named '" + name + "'" +
                    suggestionText(name, configurationNames(), "configurations"));
}

std::vector<std::string> DeploymentSet::deploymentNames() const { return keysOf(deployments_); }
std::vector<std::string> DeploymentSet::configurationNames() const { return keysOf(configurations_); }

ConfigurationSpec loadConfigurationFile(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw core::Error("cannot read configuration file " + file.string());
  return parseConfiguration(in, file.stem().string(), file.string());
}

ConfigurationSpec parseConfiguration(std::istream& in, const std::string& name, const std::string& file) {
  ConfigurationSpec configuration{name, {file, 1}, {}};
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const SourceLocation where{file, number};
    const std::string text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const auto equals = text.find('=');
    const std::string target = equals == std::string::npos ? "" : trim(text.substr(0, equals));
    const auto dot = target.find('.');
    if (equals == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == target.size())
      throw core::Error(where.text() + ": expected \"Component.property = value\", got \"" + text + "\"");
    configuration.values.push_back(
        {target.substr(0, dot), target.substr(dot + 1), trim(text.substr(equals + 1)), where});
  }
  return configuration;
}

std::vector<ConfigurationSpec> loadConfigurationFolder(const std::filesystem::path& folder) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error))
    throw core::Error("configuration folder " + folder.string() + " does not exist or is not a folder");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.is_regular_file() && entry.path().extension() == ".cfg") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<ConfigurationSpec> out;
  for (const auto& file : files) out.push_back(loadConfigurationFile(file));
  return out;
}

}  // namespace cobra::deploy
