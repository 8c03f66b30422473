#pragma once
/// @file
/// The role linter (ARCHITECTURE §2): checks connections against the roles of the components at both
/// ends and the data kind (pure or logic) of the connected ports.
///
/// What is checked, per connection `W.out -> R.in` carrying data of kind K:
/// - reader side: a Calculation or Decision reader must get pure data; a Supervision reader must
///   get logic data; a Bridge reader may get anything.
/// - writer side, except for the writer's own `events` port (every component may report events
///   about its own behaviour, thesis §2.1): a Calculation writes pure data; a Supervision or
///   Decision writes logic data; a Bridge writes a kind that at least one of its own input ports
///   reads (it changes representation, not kind). A Bridge without input ports is a source
///   (a sensor, a device) and may write either kind.
/// The Bridge rule looks at the input ports the component declares, connected or not, because a
/// Bridge's kinds are a property of the component, not of one deployment.

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "cobra/core/introspection.hpp"
#include "cobra/deploy/spec.hpp"

namespace cobra::deploy {

/// One broken rule on one connection.
struct LintViolation {
  std::string output;  ///< "Comp.port" of the writer
  std::string input;   ///< "Comp.port" of the reader
  core::Role output_role;
  core::Role input_role;
  std::string rule;     ///< the rule, e.g. "a Supervision component may read only logic data"
  SourceLocation where; ///< the connection entry
  /// "deploy.lua:7: Gain.out (Calculation) -> TaskSup.inputEvents (Supervision): a Supervision
  /// component may read only logic data, but double is pure data".
  std::string message;
};

/// The violations of the connection from `output` to `input` (none, one or two).
std::vector<LintViolation> lintConnection(const core::PortBase& output, const core::PortBase& input,
                                          const SourceLocation& where = {});

/// The violations of every entry of `connections` whose components and ports exist in
/// `components` (entries naming unknown ones are the deployer's errors, not the linter's).
std::vector<LintViolation> lint(const std::vector<ConnectionSpec>& connections,
                                const core::ComponentRegistry& components);

/// Finds a component by name (nullptr: none), e.g. in a registry and in the shadows of the
/// components of other hosts.
using ComponentLookup = std::function<const core::Component*(std::string_view)>;

/// As above, with the components `find` finds.
std::vector<LintViolation> lint(const std::vector<ConnectionSpec>& connections, const ComponentLookup& find);

/// One line per violation, ready to print or to put in an error.
std::string toText(const std::vector<LintViolation>& violations);

}  // namespace cobra::deploy
