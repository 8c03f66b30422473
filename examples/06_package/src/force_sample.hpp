#pragma once
// example.ForceSample: the package's own data type, a record (cobra/core/record.hpp). Registered
// in the package's entry point with cobra::types::registerType<T>() (package.cpp), it travels on
// ports and properties, is a Lua table in deployment files ({force = 10, filtered = 9.5, count = 3}),
// has CSV columns with units in a Reporter's file (Filter.sample_out.force [N], ...) and a DDS
// wire type (transport = "dds").

#include <tuple>

#include "cobra/core/record.hpp"

namespace example {

/// One update of ForceLowPass: what it read, what it wrote, and how many updates it made.
struct ForceSample {
  double force = 0.0;     // N, the force read
  double filtered = 0.0;  // N, the filter's output
  int count = 0;          // updates since start
};

}  // namespace example

template <>
struct cobra::core::DataTypeTraits<example::ForceSample> : cobra::core::RecordTraits<example::ForceSample> {
  static constexpr std::string_view name = "example.ForceSample";
  static constexpr std::string_view cpp = "example::ForceSample";
  static constexpr std::string_view header = "\"force_sample.hpp\"";
  static constexpr auto fields =
      std::tuple{field("force", &example::ForceSample::force, "N", "force read"),
                 field("filtered", &example::ForceSample::filtered, "N", "filtered force written"),
                 field("count", &example::ForceSample::count, "", "updates since start")};
};
