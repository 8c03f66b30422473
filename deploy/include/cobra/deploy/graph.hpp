#pragma once
/// @file
/// Drawing a deployment: Graphviz DOT text of its components (coloured by role, with their
/// ports) and connections (labelled with their policy), for `cobra graph`.

#include <string>

#include "cobra/core/introspection.hpp"

namespace cobra::deploy {

/// The fill colour of a role in drawings: Calculation blue, Supervision orange, Decision
/// green, Bridge grey (hex "#rrggbb").
std::string roleColour(core::Role role);

/// DOT text of every component of `registry` and every connection between their ports.
/// Components are record nodes listing inputs on the left and outputs on the right; edges go
/// from output to input with the policy ("data", "buffer(8)") as label; logic-data edges are
/// dashed. Ports connected to ports outside the registry are drawn to a plain node.
std::string graphvizDot(const core::ComponentRegistry& registry, const std::string& title = "cobra deployment");

}  // namespace cobra::deploy
