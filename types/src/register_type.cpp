#include "cobra/types/register_type.hpp"

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/types/gray_image.hpp"
#include "cobra/types/point_list.hpp"
#include "motion_types.hpp"

// cobra::types is built without the dds headers: the `cobra` tool links it, and must link neither
// cobra::dds nor Fast DDS (the transport is the package cobra_dds; types/README.md).
#ifdef COBRA_TYPES_HAVE_DDS
#error "cobra::types must be built without cobra::dds: registerBuiltins() registers core, Lua and CSV only"
#endif

namespace cobra::types {

void registerBuiltins() {
  core::forEachType(core::BuiltinDataTypes{}, [](auto type) { registerType<typename decltype(type)::type>(); });
  // cobra's types defined above core, with their codecs in this module (motion_types.hpp).
  // (TGL.MultiAxisPath has no DDS wire, no DdsCodec: a package that registers it with DDS present
  // would not compile; here there is no DDS side.)
  registerType<trajectory::MultiAxisPath>();
  // Geometry.PointList (point_list.cpp): a navigation program's plan, every capability here.
  registerPointList();
  // Imaging.GrayImage: a port type only, known to core (its name for lint, the editor's palette and
  // `cobra new component`) and to nothing else: a 64 KiB value has no Lua table, CSV cell or
  // property form worth having (gray_image.hpp), and the image ports read and write it in C++.
  (void)core::typeInfo<GrayImage>();
}

bool hasEveryCapability(const core::TypeInfo& type) {
  return script::findConversion(type) != nullptr && components::findCsvType(type) != nullptr;
}

}  // namespace cobra::types
