#include "cobra/types/register_type.hpp"

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "motion_types.hpp"

namespace cobra::types {

void registerBuiltins() {
  core::forEachType(core::BuiltinDataTypes{}, [](auto type) { registerType<typename decltype(type)::type>(); });
  // cobra's types defined above core, with their codecs in this module (motion_types.hpp).
  registerType<trajectory::MultiAxisPath>();
}

bool hasEveryCapability(const core::TypeInfo& type) {
  return script::findConversion(type) != nullptr && components::findCsvType(type) != nullptr;
}

}  // namespace cobra::types
