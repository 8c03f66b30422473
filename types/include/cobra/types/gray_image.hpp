#pragma once
/// @file
/// `cobra::types::GrayImage` ("Imaging.GrayImage", pure data): one 8-bit grey image placed in the
/// world, what a (simulated) ultrasound probe produces and the OpenIGTLink bridge sends as an IMAGE
/// message. Fixed size (at most kMaxWidth x kMaxHeight pixels, 64 KiB of pixels): no heap, so it
/// crosses real-time ports.
///
/// Geometry: `pose` is the frame of pixel (0, 0) in the world (m): its x axis runs along the
/// columns (pixel (c, r) is at pose * [c * spacing_x, r * spacing_y, 0]), its y axis along the
/// rows; the image plane is its x-y plane.
///
/// It is a port type only: DataTypeTraits give its name and a short text form ("160x120 image",
/// which does not carry the pixels, so parse refuses every text). It is not registered for Lua or
/// CSV (a 64 KiB value is no property, Lua table or CSV cell): it travels between components and
/// to the bridge, nowhere else.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <kdl/frames.hpp>

#include "cobra/core/data_type.hpp"

namespace cobra::types {

struct GrayImage {
  static constexpr std::size_t kMaxWidth = 256;   ///< pixels
  static constexpr std::size_t kMaxHeight = 256;  ///< pixels

  std::size_t width = 0;    ///< pixels per row (columns), at most kMaxWidth
  std::size_t height = 0;   ///< rows, at most kMaxHeight
  double spacing_x = 1e-3;  ///< m per pixel along a row (between columns)
  double spacing_y = 1e-3;  ///< m per pixel along a column (between rows)
  KDL::Frame pose;          ///< m: frame of pixel (0, 0) in the world; x along columns, y along rows
  std::array<std::uint8_t, kMaxWidth * kMaxHeight> pixels{};  ///< row-major: pixel (c, r) at r * width + c

  /// True when the size is within the limits (what a sender checks before using `pixels`).
  bool valid() const noexcept { return width <= kMaxWidth && height <= kMaxHeight && width * height <= pixels.size(); }
  std::uint8_t at(std::size_t column, std::size_t row) const noexcept { return pixels[row * width + column]; }
};

}  // namespace cobra::types

template <>
struct cobra::core::DataTypeTraits<cobra::types::GrayImage> {
  static constexpr std::string_view name = "Imaging.GrayImage";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format = "an image (no text form: only its size is printed, \"WxH image\")";
  static constexpr std::string_view cpp = "cobra::types::GrayImage";
  static constexpr std::string_view header = "<cobra/types/gray_image.hpp>";
  static std::string print(const cobra::types::GrayImage& value) {
    return std::to_string(value.width) + "x" + std::to_string(value.height) + " image";
  }
  /// An image has no text form that carries its pixels: every text is refused.
  static bool parse(std::string_view, cobra::types::GrayImage&) { return false; }
};
