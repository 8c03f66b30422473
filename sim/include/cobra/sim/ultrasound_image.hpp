#pragma once
/// @file
/// A B-mode-like ultrasound image of the phantom (thesis §4.2: the surgeon and the navigation
/// display see what the probe sees): the probe's imaging plane rendered into a fixed 8-bit grey
/// buffer, with the phantom's layers and their interfaces, the tumour, the forbidden regions
/// (vessels dark, ribs bright with an acoustic shadow), the needle where it lies within the beam's
/// thickness, tissue-fixed speckle and depth attenuation.
///
/// Frames as in ultrasound.hpp: the probe frame U has its origin at the centre of the transducer
/// face, z along the beam (into the body), x along the array; the imaging plane is U's x-z plane.
/// Poses are given in the phantom frame P (phantom.hpp: skin at z = 0, tissue below). Image frame I
/// (UltrasoundImage::pose): origin at the outer corner of pixel (0, 0), x along the columns (U's
/// x), y along the rows (U's z, the depth), z = x × y = -U's y. Pixel (column c, row r) covers
/// I's x in [c, c + 1)·spacing_x and y in [r, r + 1)·spacing_y; the columns are centred on the
/// probe: column width/2 starts at U's x = 0.

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/sim/phantom.hpp"

namespace cobra::sim {

/// The rendered image: the same fields as cobra::types::GrayImage (the port type), so that a
/// component copies it field by field.
struct UltrasoundImage {
  static constexpr std::size_t kMaxPixels = 65536;  ///< 256 x 256
  std::uint16_t width = 0;    ///< pixels per row (columns), along the array
  std::uint16_t height = 0;   ///< rows, along the depth
  double spacing_x = 0.0;     ///< m per pixel along a row
  double spacing_y = 0.0;     ///< m per pixel along a column
  KDL::Frame pose;            ///< frame I in P (m): the outer corner of pixel (0, 0), see the file comment
  std::array<std::uint8_t, kMaxPixels> pixels{};  ///< row-major grey levels, pixels[r * width + c]

  std::uint8_t at(int column, int row) const noexcept { return pixels[static_cast<std::size_t>(row) * width + column]; }
};

/// Echogenicity (0 = black, 1 = the brightest reflector) is the image's grey level before
/// speckle and attenuation. Every value is an ASSUMPTION chosen to read like an abdominal B-mode
/// image (bright skin and fascia, dark fat, grey muscle and kidney, an anechoic vessel, a
/// hypoechoic tumour with a bright rim, a rib's bright surface with a shadow below).
struct UltrasoundImageModel {
  int width = 128;                    ///< pixels, 1..256 (width · height <= 65536)
  int height = 128;                   ///< pixels, 1..256
  double spacing_x = 0.0008;          ///< m per pixel, > 0 (128 px: 102 mm wide)
  double spacing_y = 0.0008;          ///< m per pixel, > 0 (128 px: 102 mm deep, a tumour 60 mm down seen from 45 mm aside)
  double array_half_width = 0.02;     ///< m, > 0: half the array at the probe face (the field of view's top)
  /// rad, [0, 1.4]: the field of view widens by tan(half_sector) per m of depth (0: a linear probe)
  double half_sector = 0.35;
  /// m, > 0: the beam's elevational thickness; the needle shows within ±beam_width/2 of the plane
  double beam_width = 0.002;
  double attenuation = 6.0;           ///< 1/m, >= 0: grey level × exp(-attenuation · depth along the beam)
  double speckle = 0.55;              ///< [0, 1]: share of the grey level that is speckle (fully developed: Rayleigh amplitude)
  double speckle_grain = 0.0005;      ///< m, > 0: size of a speckle grain, fixed to the tissue (frame P)
  /// m, > 0: a layer boundary's bright line (drawn at least a pixel's half diagonal either side: no gaps)
  double interface_thickness = 0.0008;
  double rim_thickness = 0.0008;      ///< m, > 0: the tumour's and a vessel's bright rim
  /// m, > 0: the needle's bright line (drawn at least a pixel's half diagonal either side)
  double needle_width = 0.0008;
  double needle_length = 0.2;         ///< m, > 0: shaft behind the tip that can show (only below the skin does)
  std::vector<std::pair<std::string, double>> layer_echo = {
      {"skin", 0.7}, {"fat", 0.25}, {"muscle", 0.5}, {"kidney", 0.42}};  ///< by layer name, [0, 1]
  double other_layer_echo = 0.4;      ///< [0, 1]: a layer not named above
  double deep_echo = 0.3;             ///< [0, 1]: below the last layer
  double interface_echo = 0.8;        ///< [0, 1]: layer boundaries
  double tumour_echo = 0.1;            ///< [0, 1]: inside the tumour (hypoechoic)
  double rim_echo = 0.75;              ///< [0, 1]: the tumour's rim, a vessel's wall
  double vessel_echo = 0.02;          ///< [0, 1]: inside a forbidden region that is not bone (anechoic blood)
  double bone_echo = 1.0;             ///< [0, 1]: a bone's (rib's) surface
  double shadow = 0.06;               ///< [0, 1]: what is left below a bone surface along the scan line
  double needle_echo = 1.0;           ///< [0, 1]: the needle (a specular steel reflector)
};

/// @throws std::invalid_argument "ultrasound image: PARAMETER = VALUE, expected RANGE UNIT".
void validate(const UltrasoundImageModel& model);

/// Renders the phantom as a probe sees it. Construction copies the phantom's geometry into fixed
/// tables (allocates); render() is noexcept, allocation-free and deterministic: the speckle is a
/// function of the seed and of the tissue point, so the same seed, probe and needle give the same
/// image, and the speckle stays with the tissue when the probe moves.
///
/// Nothing above the skin (z > 0 in P) nor outside the field of view is imaged (grey 0), and a
/// probe whose face centre is above the skin is not coupled: its image is black. The face couples
/// through its centre whatever its tilt (a convex face), so a tilted face images all the tissue
/// in its plane. Scan lines are the image columns (along U's z): below a bone's surface a column
/// keeps `shadow` of its grey level.
/// Forbidden regions whose name contains "rib" or "bone" are bone; any other is fluid (a vessel).
class UltrasoundImager {
 public:
  /// @throws std::invalid_argument from validate(model) and validate(phantom).
  UltrasoundImager(const UltrasoundImageModel& model, const PhantomScenario& phantom, std::uint64_t seed);

  /// Fills `image` (size, spacing, pose and pixels) for a probe pose and, unless `needle_tip` is
  /// null, the needle's tip frame (z along the needle, as in NeedleTissueModel); both in P (m).
  void render(const KDL::Frame& probe, const KDL::Frame* needle_tip, UltrasoundImage& image) const noexcept;

  /// render() of the columns [first_column, end_column) only (clamped to the image's width): the
  /// size, spacing and pose, and those columns' pixels, exactly as render() writes them; the other
  /// pixels are left as they are. The columns are the scan lines and each is computed on its own
  /// (a bone's shadow runs down its column), so rendering the image in bands of columns with the
  /// same poses gives render()'s image bit for bit: a real-time caller spreads the image over
  /// several steps this way. noexcept, allocation-free.
  void renderColumns(const KDL::Frame& probe, const KDL::Frame* needle_tip, UltrasoundImage& image, int first_column,
                     int end_column) const noexcept;

  /// Frame I in P for a probe pose (what render() writes into image.pose).
  KDL::Frame imagePose(const KDL::Frame& probe) const noexcept;

  const UltrasoundImageModel& model() const noexcept { return model_; }

 private:
  static constexpr std::size_t kMaxLayers = 16;
  static constexpr std::size_t kMaxRegions = 16;

  struct Region {
    KDL::Vector a, ab;     // m: axis start, axis (b - a)
    double ab2 = 0.0;      // m²: |ab|²
    double radius = 0.0;   // m
    bool bone = false;
  };

  double speckle(const KDL::Vector& p) const noexcept;

  UltrasoundImageModel model_;
  std::uint64_t seed_ = 0;
  std::size_t layer_count_ = 0;
  std::array<double, kMaxLayers> layer_bottom_{};  // m: depth of each layer's bottom
  std::array<double, kMaxLayers> layer_echo_{};
  std::size_t region_count_ = 0;
  std::array<Region, kMaxRegions> regions_{};
  KDL::Vector tumour_center_;
  double tumour_radius_ = 0.0;
};

}  // namespace cobra::sim
