#pragma once
/// @file
/// One description of a deployment (thesis §3.2.1-3.2.2: OroEdit's project, the Configurator's
/// tables): what `cobra describe` writes back from a live Configurator, what the studio's editor
/// edits and saves. It is made from a Configurator (describe), written as a Lua deployment file
/// (toLua: the one writer) and read back by running that file (LuaDeployer) and describing again;
/// the text is stable through that round trip: toLua(describe(load(toLua(d)))) == toLua(d) for a
/// description d made by describe.
///
/// What is written (and so what describe keeps):
/// - property values that differ from the value a freshly made component of the same type has,
///   except read-only properties (set by the component itself) and properties a fresh component
///   does not have (made when it configures, e.g. from a chart file);
/// - the connections connectPorts made (Configurator::madeConnections; those of the applied
///   deployments come back with applyDeployment, those components make themselves with them);
///   connections to ports outside the deployment are counted only;
/// - activities, except those an applied deployment sets to the same values and the event-driven
///   one (period 0, priority 0, ORO_SCHED_OTHER) every component has until it is given another;
/// - the configure list (every configured component, in the order they were made: a component
///   may make ports when it configures that a deployment connects), the start list (the running
///   components outside the applied deployments), then the applied deployment of each scope and
///   the configuration last applied.

#include <string>
#include <string_view>
#include <vector>

#include "cobra/core/conn_policy.hpp"
#include "cobra/deploy/configurator.hpp"

namespace cobra::deploy {

/// One property value set on a component before it is configured.
struct PropertyValueDescription {
  std::string component;
  std::string property;
  std::string type;   ///< the property's type name (core TypeInfo::name: "double", "KDL.Frame", ...)
  std::string value;  ///< text form of `type` (core DataTypeTraits<T>::print/parse)
};

/// A whole deployment, as the Configurator tables of a Lua deployment file hold it.
struct DeploymentDescription {
  std::vector<std::string> packages;
  std::vector<ComponentSpec> components;
  std::vector<PropertyValueDescription> properties;
  std::vector<ActivitySpec> activities;
  std::vector<PeerSpec> peers;
  /// Made by connectPorts (the named deployments' own connections are in `deployments`).
  std::vector<ConnectionSpec> connections;
  std::vector<DeploymentSpec> deployments;
  std::vector<ConfigurationSpec> configurations;  ///< values as text, as in configuration files
  std::vector<std::string> configure;  ///< configureComponents, in this order
  std::vector<std::string> start;      ///< startComponents, in this order
  std::vector<std::string> apply;      ///< applyDeployment, in this order (one per scope)
  std::string configuration;           ///< applyConfiguration last ("" for none)
  int outside_connections = 0;         ///< connections to ports outside the deployment (not listed)
  /// setExecutor (its `declared` false when the files have none); its component `Executor` is not
  /// among `components`: setExecutor makes it.
  ExecutorSpec executor;
};

/// The description of what `configurator` deployed (see the file comment for what is kept).
/// Makes one component of each used type through the configurator's packages to learn the
/// default property values. Call it between two advances of the lockstep clock (or with nothing
/// running): it reads property values as text through the components' thread-safe accessors.
DeploymentDescription describe(const Configurator& configurator);

/// `d` in the form describe gives back for the file toLua writes of it (what the editor saves):
/// activities, peers, configure and start lists in the components' order, default activities and
/// those the applied deployments set dropped, the applied deployments' components configured
/// and not started by startComponents, their connections left to them, deployments and
/// configurations by name, applied deployments in the order of their scopes' first deployment.
/// Property values equal to a type's default are the caller's to drop (it knows the types).
DeploymentDescription canonical(DeploymentDescription d);

/// The Lua deployment file of `description`: packages_list, components_list, the property
/// assignments, activities_list, peers_list, connections_list, defineDeployment and
/// defineConfiguration calls, then initConfigurator ... applyConfiguration. `cobra deploy` and
/// `cobra run` read it; describing it again gives the same text.
std::string toLua(const DeploymentDescription& description);

/// The policy table a Lua file writes for `spec`: `{ type = "buffer", size = 16 }`, with
/// `transport`, `topic` and `qos = { key = "value" }` when it names a transport.
std::string luaPolicyTable(const ConnPolicySpec& spec);
/// The spec that gives `policy` back through toConnPolicy (the writer's seam for live channels).
ConnPolicySpec connPolicySpecOf(const core::ConnPolicy& policy);

/// The Lua value that sets a property of type `type` (core type name) to `text` through a
/// component reference, in the form script/convert.hpp reads: double and int as numbers
/// (math.huge for inf, math.abs(0/0) for nan; an int must be integral), bool as true/false,
/// vector<double> and KDL.JntArray as arrays of numbers, KDL.Vector, Rotation, Frame, Twist and
/// Wrench as arrays of 3, 4, 7, 6 and 6 numbers, an Event as its name or `{ name = , source = ,
/// stamp = }`, a string and every other registered type (TaskState, a package's own) as a string
/// (its text form, which Lua sets through Property::setFromText).
/// @throws core::Error "expected ..." when `text` is not a value of `type`, or "type 'T' has no
///         Lua form ..." for a type this process has not registered.
std::string luaValue(std::string_view type, std::string_view text);
/// `text` as a Lua string literal (double quotes, escaped).
std::string luaString(std::string_view text);

}  // namespace cobra::deploy
