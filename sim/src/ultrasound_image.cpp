#include "cobra/sim/ultrasound_image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace cobra::sim {
namespace {

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

[[noreturn]] void reject(const std::string& parameter, double value, const std::string& expected) {
  throw std::invalid_argument("ultrasound image: " + parameter + " = " + number(value) + ", expected " + expected);
}

void requirePositive(const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) reject(parameter, value, std::string("> 0 ") + unit);
}

void requireRange(const std::string& parameter, double value, double low, double high, const char* unit = "") {
  if (!std::isfinite(value) || value < low || value > high) {
    reject(parameter, value, "in [" + number(low) + ", " + number(high) + "]" + unit);
  }
}

/// splitmix64's finaliser (Steele, Lea, Flood, OOPSLA 2014): a well-mixed 64-bit hash.
std::uint64_t mix(std::uint64_t z) noexcept {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A uniform value in [0, 1) for lattice point (i, j, k) of a seed's speckle field.
double latticeValue(std::uint64_t seed, std::int64_t i, std::int64_t j, std::int64_t k) noexcept {
  const std::uint64_t h = mix(seed + static_cast<std::uint64_t>(i) * 0x9e3779b97f4a7c15ULL +
                              static_cast<std::uint64_t>(j) * 0xc2b2ae3d27d4eb4fULL +
                              static_cast<std::uint64_t>(k) * 0x165667b19e3779f9ULL);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

/// Distance from (x, z) to the 2-D segment p-q.
double segmentDistance2d(double x, double z, double px, double pz, double qx, double qz) noexcept {
  const double dx = qx - px, dz = qz - pz, length2 = dx * dx + dz * dz;
  const double t = length2 > 0.0 ? std::clamp(((x - px) * dx + (z - pz) * dz) / length2, 0.0, 1.0) : 0.0;
  const double ex = x - (px + t * dx), ez = z - (pz + t * dz);
  return std::sqrt(ex * ex + ez * ez);
}

}  // namespace

void validate(const UltrasoundImageModel& m) {
  requireRange("width", m.width, 1, 256, " px");
  requireRange("height", m.height, 1, 256, " px");
  requirePositive("spacing_x", m.spacing_x, "m");
  requirePositive("spacing_y", m.spacing_y, "m");
  requirePositive("array_half_width", m.array_half_width, "m");
  requireRange("half_sector", m.half_sector, 0.0, 1.4, " rad");
  requirePositive("beam_width", m.beam_width, "m");
  requireRange("attenuation", m.attenuation, 0.0, 1e3, " 1/m");
  requireRange("speckle", m.speckle, 0.0, 1.0);
  requirePositive("speckle_grain", m.speckle_grain, "m");
  requirePositive("interface_thickness", m.interface_thickness, "m");
  requirePositive("rim_thickness", m.rim_thickness, "m");
  requirePositive("needle_width", m.needle_width, "m");
  requirePositive("needle_length", m.needle_length, "m");
  for (const auto& [name, echo] : m.layer_echo) requireRange("layer_echo[" + name + "]", echo, 0.0, 1.0);
  const std::pair<const char*, double> echoes[] = {
      {"other_layer_echo", m.other_layer_echo}, {"deep_echo", m.deep_echo},     {"interface_echo", m.interface_echo},
      {"tumour_echo", m.tumour_echo},           {"rim_echo", m.rim_echo},       {"vessel_echo", m.vessel_echo},
      {"bone_echo", m.bone_echo},               {"shadow", m.shadow},           {"needle_echo", m.needle_echo}};
  for (const auto& [name, echo] : echoes) requireRange(name, echo, 0.0, 1.0);
}

UltrasoundImager::UltrasoundImager(const UltrasoundImageModel& model, const PhantomScenario& phantom, std::uint64_t seed)
    : model_(model), seed_(seed) {
  validate(model_);
  validate(phantom);
  if (phantom.layers.size() > kMaxLayers) {
    throw std::invalid_argument("ultrasound image: the phantom has " + std::to_string(phantom.layers.size()) +
                                " layers, expected at most " + std::to_string(kMaxLayers));
  }
  if (phantom.forbidden.size() > kMaxRegions) {
    throw std::invalid_argument("ultrasound image: the phantom has " + std::to_string(phantom.forbidden.size()) +
                                " forbidden regions, expected at most " + std::to_string(kMaxRegions));
  }
  layer_count_ = phantom.layers.size();
  for (std::size_t i = 0; i < layer_count_; ++i) {
    const TissueLayer& layer = phantom.layers[i];
    layer_bottom_[i] = layerTop(phantom, i) + layer.thickness;
    layer_echo_[i] = model_.other_layer_echo;
    for (const auto& [name, echo] : model_.layer_echo) {
      if (name == layer.tissue.name) layer_echo_[i] = echo;
    }
  }
  region_count_ = phantom.forbidden.size();
  for (std::size_t i = 0; i < region_count_; ++i) {
    const ForbiddenRegion& f = phantom.forbidden[i];
    Region& r = regions_[i];
    r.a = f.a;
    r.ab = f.b - f.a;
    r.ab2 = KDL::dot(r.ab, r.ab);
    r.radius = f.radius;
    r.bone = f.name.find("rib") != std::string::npos || f.name.find("bone") != std::string::npos;
  }
  tumour_center_ = phantom.tumour_center;
  tumour_radius_ = phantom.tumour_radius;
}

KDL::Frame UltrasoundImager::imagePose(const KDL::Frame& probe) const noexcept {
  const KDL::Vector x = probe.M.UnitX(), y = probe.M.UnitZ();
  return KDL::Frame(KDL::Rotation(x, y, x * y), probe.p - x * (0.5 * model_.width * model_.spacing_x));
}

/// Fully developed speckle: a Rayleigh-distributed echo amplitude (what B-mode displays, before
/// log compression), here of a smooth random field (trilinear interpolation of a hashed lattice
/// of `speckle_grain` m in P), so that a grain is about that size and belongs to the tissue, not
/// to the pixel. Mean about 1.
double UltrasoundImager::speckle(const KDL::Vector& p) const noexcept {
  const double inv = 1.0 / model_.speckle_grain;
  const double gx = p.x() * inv, gy = p.y() * inv, gz = p.z() * inv;
  const double fx = std::floor(gx), fy = std::floor(gy), fz = std::floor(gz);
  const double tx = gx - fx, ty = gy - fy, tz = gz - fz;
  const auto i = static_cast<std::int64_t>(fx), j = static_cast<std::int64_t>(fy), k = static_cast<std::int64_t>(fz);
  double value = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
    const double weight = (di ? tx : 1.0 - tx) * (dj ? ty : 1.0 - ty) * (dk ? tz : 1.0 - tz);
    value += weight * latticeValue(seed_, i + di, j + dj, k + dk);
  }
  // The interpolated value gathers towards 0.5: stretch it back before the exponential's inverse.
  const double u = std::clamp(0.5 + 1.7 * (value - 0.5), 0.0, 0.995);
  constexpr double kUnitMean = 0.7978845608028654;  // 1 / sqrt(pi / 2): the Rayleigh's mean made 1
  return kUnitMean * std::sqrt(-2.0 * std::log1p(-u));
}

void UltrasoundImager::render(const KDL::Frame& probe, const KDL::Frame* needle_tip, UltrasoundImage& image) const noexcept {
  renderColumns(probe, needle_tip, image, 0, model_.width);
}

void UltrasoundImager::renderColumns(const KDL::Frame& probe, const KDL::Frame* needle_tip, UltrasoundImage& image,
                                     int first_column, int end_column) const noexcept {
  const UltrasoundImageModel& m = model_;
  first_column = std::clamp(first_column, 0, m.width);
  end_column = std::clamp(end_column, first_column, m.width);
  image.width = static_cast<std::uint16_t>(m.width);
  image.height = static_cast<std::uint16_t>(m.height);
  image.spacing_x = m.spacing_x;
  image.spacing_y = m.spacing_y;
  image.pose = imagePose(probe);

  const KDL::Vector ux = probe.M.UnitX(), uy = probe.M.UnitY(), uz = probe.M.UnitZ(), origin = probe.p;
  // A line at least as thick as a pixel's half diagonal lights every pixel it passes through.
  const double pixel = std::hypot(m.spacing_x, m.spacing_y);
  const double interface_half = std::max(0.5 * m.interface_thickness, 0.5 * pixel);
  const double rim_half = std::max(0.5 * m.rim_thickness, 0.5 * pixel);
  const double needle_half = std::max(0.5 * m.needle_width, 0.5 * pixel);
  const double bone_surface = std::max(m.interface_thickness, m.spacing_y);
  const double spread = std::tan(m.half_sector);

  // The tumour's section by the plane: a disc of radius rho about (tumour_x, tumour_z) in U.
  const KDL::Vector to_tumour = tumour_center_ - origin;
  const double tumour_off = KDL::dot(to_tumour, uy);
  const bool tumour_cut = std::abs(tumour_off) < tumour_radius_;
  const double rho = tumour_cut ? std::sqrt(tumour_radius_ * tumour_radius_ - tumour_off * tumour_off) : 0.0;
  const double tumour_x = KDL::dot(to_tumour, ux), tumour_z = KDL::dot(to_tumour, uz);

  // The needle's part within the beam's thickness, projected on the plane: (n0x, n0z)-(n1x, n1z) in U.
  bool needle_seen = false;
  double n0x = 0.0, n0z = 0.0, n1x = 0.0, n1z = 0.0;
  if (needle_tip != nullptr) {
    // Shaft point s m behind the tip: tip - axis · s; its distance to the plane: off0 - s · slope.
    const KDL::Vector axis = needle_tip->M.UnitZ(), to_tip = needle_tip->p - origin;
    const double off0 = KDL::dot(to_tip, uy), slope = KDL::dot(axis, uy), half = 0.5 * m.beam_width;
    double s0 = 0.0, s1 = m.needle_length;
    if (std::abs(slope) < 1e-12) {
      needle_seen = std::abs(off0) <= half;
    } else {
      const double a = (off0 - half) / slope, b = (off0 + half) / slope;
      s0 = std::max(s0, std::min(a, b));
      s1 = std::min(s1, std::max(a, b));
      needle_seen = s0 <= s1;
    }
    const KDL::Vector p0 = to_tip - axis * s0, p1 = to_tip - axis * s1;
    n0x = KDL::dot(p0, ux), n0z = KDL::dot(p0, uz), n1x = KDL::dot(p1, ux), n1z = KDL::dot(p1, uz);
  }

  // Coupling through the face's centre (a convex face touches the skin there first): lifted off
  // the skin, the probe sees nothing.
  if (probe.p.z() > 0.0) {
    for (int r = 0; r < m.height; ++r) {
      const auto row = image.pixels.begin() + static_cast<std::ptrdiff_t>(r) * m.width;
      std::fill(row + first_column, row + end_column, std::uint8_t{0});
    }
    return;
  }
  std::array<double, 256> row_gain{};  // depth attenuation per row
  for (int r = 0; r < m.height; ++r) row_gain[static_cast<std::size_t>(r)] = std::exp(-m.attenuation * (r + 0.5) * m.spacing_y);

  for (int c = first_column; c < end_column; ++c) {
    const double x = (c + 0.5 - 0.5 * m.width) * m.spacing_x;
    double bone_depth = -1.0;     // m along the beam where the scan line entered bone (< 0: not yet)
    for (int r = 0; r < m.height; ++r) {
      const double z = (r + 0.5) * m.spacing_y;
      std::uint8_t& out = image.pixels[static_cast<std::size_t>(r) * m.width + c];
      const KDL::Vector q = origin + ux * x + uz * z;
      const double depth = -q.z();
      if (depth < 0.0 || std::abs(x) > m.array_half_width + z * spread) {
        out = 0;
        continue;
      }
      // Layers and their boundaries (the skin's top at depth 0 included).
      double echo = m.deep_echo;
      for (std::size_t i = 0; i < layer_count_; ++i) {
        if (depth < layer_bottom_[i]) {
          echo = layer_echo_[i];
          break;
        }
      }
      bool specular = depth <= interface_half;
      for (std::size_t i = 0; i < layer_count_ && !specular; ++i) specular = std::abs(depth - layer_bottom_[i]) <= interface_half;
      if (specular) echo = m.interface_echo;
      // The tumour: hypoechoic disc, bright rim.
      if (tumour_cut) {
        const double dx = x - tumour_x, dz = z - tumour_z;
        const double radial = std::sqrt(dx * dx + dz * dz) - rho;
        if (std::abs(radial) <= rim_half) {
          echo = m.rim_echo;
          specular = true;
        } else if (radial < 0.0) {
          echo = m.tumour_echo;
          specular = false;
        }
      }
      // Forbidden regions: fluid (anechoic, bright wall) or bone (bright surface, shadow below).
      for (std::size_t i = 0; i < region_count_; ++i) {
        const Region& region = regions_[i];
        const KDL::Vector aq = q - region.a;
        const double t = region.ab2 > 0.0 ? std::clamp(KDL::dot(aq, region.ab) / region.ab2, 0.0, 1.0) : 0.0;
        const KDL::Vector off_axis = aq - region.ab * t;
        const double reach = region.radius + rim_half, distance2 = KDL::dot(off_axis, off_axis);
        if (distance2 > reach * reach) continue;  // clear of the region and its wall
        const double distance = std::sqrt(distance2) - region.radius;
        if (region.bone) {
          if (distance <= 0.0 && bone_depth < 0.0) bone_depth = z;
        } else if (std::abs(distance) <= rim_half) {
          echo = m.rim_echo;
          specular = true;
        } else if (distance < 0.0) {
          echo = m.vessel_echo;
          specular = false;
        }
      }
      double gain = row_gain[static_cast<std::size_t>(r)];
      if (bone_depth >= 0.0) {
        if (z - bone_depth <= bone_surface) {
          echo = m.bone_echo;
          specular = true;
        } else {
          gain *= m.shadow;
        }
      }
      if (needle_seen && segmentDistance2d(x, z, n0x, n0z, n1x, n1z) <= needle_half) {
        echo = m.needle_echo;
        specular = true;
      }
      // Specular reflectors carry a third of the speckle of diffuse tissue.
      const double share = specular ? m.speckle / 3.0 : m.speckle;
      const double grey = echo * ((1.0 - share) + share * speckle(q)) * gain;
      out = static_cast<std::uint8_t>(std::clamp(std::lround(255.0 * grey), 0L, 255L));
    }
  }
}

}  // namespace cobra::sim
