#pragma once
// Internal to the Reporter: the Source of a reported port, made through the CSV registry
// (csv_codec.hpp), or from the port's text form for a type without a CSV codec.

#include <cstddef>
#include <memory>
#include <string>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/port.hpp"

namespace cobra::components::reporting_detail {

using components::RowWriter;

/// True for the types whose number of columns `reportPort` must be told (vector<double>, JntArray).
bool needsLength(const core::TypeInfo& type);

/// A Source reading `output` through a new reader port called `reader_name` (not yet connected).
/// @param elements the number of columns for the types of `needsLength`, otherwise 0.
/// @throws core::Error (message without the Reporter's name) when `elements` does not fit the type.
std::unique_ptr<Source> makeSource(core::OutputPortBase& output, std::string reader_name, std::size_t elements);

}  // namespace cobra::components::reporting_detail
