// libFuzzer target: the text form of every built-in port/property type (what the console,
// configuration files and operation calls from text go through). Checks that parsing never
// crashes and that print and parse agree: a parsed value prints to text that parses back to a
// value printing the same (for Event, whose printed form is richer, that it starts with the name).
// Rotations and frames are stored as matrices and printed as quaternions: the conversion is exact
// only to rounding, so their printed text parses back to the same value within 1e-12.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/data_type.hpp"

namespace {

template <class T>
void roundTrip(std::string_view text) {
  using Traits = cobra::core::DataTypeTraits<T>;
  T value{};
  if (!Traits::parse(text, value)) return;
  const std::string printed = Traits::print(value);
  T again{};
  if (!Traits::parse(printed, again)) std::abort();  // printed text must parse
  if (Traits::print(again) != printed) std::abort();  // and print the same
}

template <class T>
void roundTripApprox(std::string_view text) {
  using Traits = cobra::core::DataTypeTraits<T>;
  T value{};
  if (!Traits::parse(text, value)) return;
  T again{};
  if (!Traits::parse(Traits::print(value), again)) std::abort();  // printed text must parse
  if (!KDL::Equal(value, again, 1e-12)) std::abort();               // to the same value
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 12) {
    case 0: roundTrip<double>(text); break;
    case 1: roundTrip<int>(text); break;
    case 2: roundTrip<bool>(text); break;
    case 3: roundTrip<std::string>(text); break;
    case 4: roundTrip<std::vector<double>>(text); break;
    case 5: roundTrip<KDL::Vector>(text); break;
    case 6: roundTripApprox<KDL::Rotation>(text); break;
    case 7: roundTripApprox<KDL::Frame>(text); break;
    case 8: roundTrip<KDL::Twist>(text); break;
    case 9: roundTrip<KDL::Wrench>(text); break;
    case 10: roundTrip<KDL::JntArray>(text); break;
    default: {
      // An Event's text form is its name only; its printed form adds source and time.
      cobra::core::Event event;
      if (cobra::core::DataTypeTraits<cobra::core::Event>::parse(text, event) &&
          cobra::core::DataTypeTraits<cobra::core::Event>::print(event).rfind(event.name.str(), 0) != 0)
        std::abort();
      break;
    }
  }
  return 0;
}
