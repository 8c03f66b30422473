#include "cobra/types/register_type.hpp"

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

namespace cobra::types {

void registerBuiltins() {
  core::forEachType(core::BuiltinDataTypes{}, [](auto type) { registerType<typename decltype(type)::type>(); });
}

bool hasEveryCapability(const core::TypeInfo& type) {
  return script::findConversion(type) != nullptr && components::findCsvType(type) != nullptr;
}

}  // namespace cobra::types
