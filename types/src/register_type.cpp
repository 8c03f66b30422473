#include "cobra/types/register_type.hpp"

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "motion_types.hpp"

namespace cobra::types {

void registerBuiltins() {
  core::forEachType(core::BuiltinDataTypes{}, [](auto type) { registerType<typename decltype(type)::type>(); });
  // cobra's types defined above core, with their codecs in this module (motion_types.hpp).
  // TGL.MultiAxisPath has no DDS wire (no DdsCodec): core, Lua and CSV only, or registerType<T>()
  // would not compile where dds is present.
  (void)core::typeInfo<trajectory::MultiAxisPath>();
  script::registerLuaType<trajectory::MultiAxisPath>();
  components::registerCsvType<trajectory::MultiAxisPath>();
}

bool hasEveryCapability(const core::TypeInfo& type) {
  return script::findConversion(type) != nullptr && components::findCsvType(type) != nullptr;
}

}  // namespace cobra::types
