// libFuzzer target: the configuration file parser of the deployer (`Component.property =
// value` lines). Checks that any text either parses into well-formed entries or is refused
// with a cobra::core::Error that names the file and a line, and never crashes.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "cobra/core/error.hpp"
#include "cobra/deploy/deployment_set.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const cobra::deploy::ConfigurationSpec spec = cobra::deploy::parseConfiguration(in, "fuzz", "fuzz.cfg");
    int previous_line = 0;
    for (const auto& value : spec.values) {
      if (value.component.empty() || value.property.empty()) std::abort();
      if (value.component.find('.') != std::string::npos) std::abort();  // split at the first '.'
      if (value.where.file != "fuzz.cfg" || value.where.line <= previous_line) std::abort();
      previous_line = value.where.line;
    }
  } catch (const cobra::core::Error& e) {
    if (std::string(e.what()).rfind("fuzz.cfg:", 0) != 0) std::abort();  // errors name file:line
  }
  return 0;
}
