#pragma once
// A component's property read by name at setup, for what cobra studio draws from properties (the
// fixed extras, a kinematics solver's chain).

#include <stdexcept>
#include <string>
#include <vector>

#include "cobra/core/introspection.hpp"
#include "cobra/core/property.hpp"
#include "cobra/deploy/suggest.hpp"

namespace cobra::studio {

// The property `path` ("Comp.property") of type T, read at setup.
// @throws std::runtime_error "WHERE: USE: unknown component ...", "... has no property ...; did you
//         mean ...", or "... is a TYPE; expected EXPECTED".
template <class T>
T readProperty(const core::ComponentRegistry& registry, const std::string& path, const std::string& where,
               const std::string& use, const std::string& expected) {
  const auto dot = path.find('.');
  const std::string component = path.substr(0, dot), name = path.substr(dot + 1);
  const core::Component* c = registry.find(component);
  if (c == nullptr) {
    std::vector<std::string> names;
    for (const core::Component* each : registry.components()) names.push_back(each->name());
    throw std::runtime_error(where + ": " + use + ": unknown component '" + component + "'" +
                             deploy::suggestionText(component, names, "components"));
  }
  const core::PropertyBase* p = c->findProperty(name);
  if (p == nullptr) {
    std::vector<std::string> names;
    for (const core::PropertyBase* each : c->properties()) names.push_back(each->name());
    throw std::runtime_error(where + ": " + use + ": component '" + component + "' has no property '" + name + "'" +
                             deploy::suggestionText(name, names, "properties"));
  }
  const auto* typed = dynamic_cast<const core::Property<T>*>(p);
  if (typed == nullptr)
    throw std::runtime_error(where + ": " + use + ": property " + path + " is a " + std::string(p->type().name) +
                             "; expected " + expected);
  return typed->value();
}

}  // namespace cobra::studio
