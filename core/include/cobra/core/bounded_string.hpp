#pragma once
/// @file
/// Fixed-capacity string used in real-time data (event names): copying it never allocates.

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace cobra::core {

/// A string of at most `Capacity` characters stored inline. Trivially copyable, so values that
/// contain it travel through ports without touching the heap. Assigning a longer text keeps the
/// first `Capacity` characters; `assign` reports whether that happened.
template <std::size_t Capacity>
class BoundedString {
 public:
  constexpr BoundedString() = default;
  constexpr BoundedString(std::string_view text) { assign(text); }  // NOLINT: implicit by design
  constexpr BoundedString(const char* text) : BoundedString(std::string_view(text)) {}  // NOLINT

  /// Copies `text`; returns false when it had to be truncated to `Capacity` characters.
  constexpr bool assign(std::string_view text) {
    size_ = std::min(text.size(), Capacity);
    std::copy_n(text.data(), size_, chars_.data());
    return size_ == text.size();
  }

  constexpr std::string_view view() const { return {chars_.data(), size_}; }
  constexpr operator std::string_view() const { return view(); }  // NOLINT: implicit by design
  std::string str() const { return std::string(view()); }
  constexpr std::size_t size() const { return size_; }
  constexpr bool empty() const { return size_ == 0; }
  static constexpr std::size_t capacity() { return Capacity; }

  friend constexpr bool operator==(const BoundedString& a, const BoundedString& b) {
    return a.view() == b.view();
  }
  friend constexpr bool operator==(const BoundedString& a, std::string_view b) { return a.view() == b; }
  friend constexpr bool operator==(const BoundedString& a, const char* b) { return a.view() == std::string_view(b); }

 private:
  std::array<char, Capacity> chars_{};
  std::size_t size_ = 0;
};

}  // namespace cobra::core
