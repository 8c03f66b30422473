// registerType<Probe>() as the `cobra` tool and cobra::types compile it: without the dds headers
// (this object library links cobra::types only). Linked into register_type_dds_test.
#include "cobra/types/register_type.hpp"

#include "probe_record.hpp"

#ifdef COBRA_TYPES_HAVE_DDS
#error "register_without_dds.cpp must be compiled without the dds headers (link cobra::types only)"
#endif

namespace types_test {
Registration probeRegistrationWithoutDds() { return &cobra::types::registerType<Probe>; }
}  // namespace types_test
