// The simulated B-mode image: the tumour's section where the plane cuts it, layer interfaces at the
// phantom's depths, the needle's line in plane and not when the plane is turned, ribs and vessels,
// nothing above the skin or outside the field of view, reproducible speckle, no allocation, the
// image rendered in bands of columns the same as whole.
// COBRA_US_IMAGE_PGM=<path> makes the needle test write its image there (a PGM file).

#include "cobra/sim/ultrasound_image.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <numbers>
#include <random>

#include "cobra/test_support/counting_new.hpp"
#include "cobra/test_support/test_support.hpp"

namespace {

using cobra::sim::UltrasoundImage;
using cobra::sim::UltrasoundImageModel;
using cobra::sim::UltrasoundImager;

const std::string kPhantom = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles/phantom.txt";

/// The probe face at `face` (frame P), its beam towards `target`, its array along `array`
/// (made orthogonal to the beam): as apps/puncturing/tools/probe_plan.py builds a probe pose.
KDL::Frame probeLookingAt(const KDL::Vector& face, const KDL::Vector& target, const KDL::Vector& array) {
  KDL::Vector z = target - face;
  z.Normalize();
  KDL::Vector x = array - z * KDL::dot(array, z);
  x.Normalize();
  return {KDL::Rotation(x, z * x, z), face};
}

/// A model with exact grey levels: no speckle, no attenuation.
UltrasoundImageModel flatModel() {
  UltrasoundImageModel m;
  m.speckle = 0.0;
  m.attenuation = 0.0;
  return m;
}

/// The model's echogenicity of a named layer.
double layerEcho(const UltrasoundImageModel& m, const std::string& name) {
  for (const auto& [layer, echo] : m.layer_echo) {
    if (layer == name) return echo;
  }
  return m.other_layer_echo;
}

std::uint8_t grey(double echo) { return static_cast<std::uint8_t>(std::lround(255.0 * echo)); }

/// Where a point of P falls in the image: frame I's x, y (m) and its distance off the plane (z).
KDL::Vector imageXY(const UltrasoundImage& image, const KDL::Vector& p) { return image.pose.Inverse(p); }

/// The pixel (column, row) that contains a point of P.
std::pair<int, int> pixelOf(const UltrasoundImage& image, const KDL::Vector& p) {
  const KDL::Vector i = imageXY(image, p);
  return {static_cast<int>(std::floor(i.x() / image.spacing_x)), static_cast<int>(std::floor(i.y() / image.spacing_y))};
}

/// Frame I's x, y (m) of pixel (column, row)'s centre.
KDL::Vector centreOf(const UltrasoundImage& image, int column, int row) {
  return {(column + 0.5) * image.spacing_x, (row + 0.5) * image.spacing_y, 0.0};
}

/// The point of P at the centre of pixel (column, row).
KDL::Vector pointOf(const UltrasoundImage& image, int column, int row) { return image.pose * centreOf(image, column, row); }

/// Whether a pixel of grey level `value` lies within `rows` rows and `columns` columns of (column, row).
bool anyNear(const UltrasoundImage& image, int column, int row, int columns, int rows, std::uint8_t value) {
  for (int r = std::max(0, row - rows); r <= std::min(image.height - 1, row + rows); ++r) {
    for (int c = std::max(0, column - columns); c <= std::min(image.width - 1, column + columns); ++c) {
      if (image.at(c, r) == value) return true;
    }
  }
  return false;
}

void writePgm(const UltrasoundImage& image, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << image.width << " " << image.height << "\n255\n";
  out.write(reinterpret_cast<const char*>(image.pixels.data()), static_cast<std::streamsize>(image.width) * image.height);
}

/// Two_needles' first needle (apps/puncturing/scenarios/two_needles/cryo_plan.txt): tip frame, z along it.
struct Needle {
  KDL::Vector entry{-0.02, -0.006, 0.0}, target{-0.005, 0.0, -0.058};
  KDL::Frame tip() const {
    KDL::Vector z = target - entry;
    z.Normalize();
    KDL::Vector x = KDL::Vector(1, 0, 0) - z * z.x();
    x.Normalize();
    return {KDL::Rotation(x, z * x, z), target};
  }
  /// The probe of probe_plan.py: 45 mm beyond the tip, seen from above, in the needle's vertical plane.
  KDL::Frame probe() const {
    KDL::Vector u(target.x() - entry.x(), target.y() - entry.y(), 0.0);
    const double reach = u.Normalize();
    KDL::Vector face = entry + u * (reach + 0.045);
    face.z(0.0);
    return probeLookingAt(face, target, u);
  }
};

/// Half the width a line of `width` m is drawn with (at least a pixel's half diagonal).
double drawnHalf(const UltrasoundImageModel& m, double width) {
  return std::max(0.5 * width, 0.5 * std::hypot(m.spacing_x, m.spacing_y));
}

/// Expects the tumour's dark disc (exact grey levels: flatModel) centred on `section` (P) within a
/// pixel, its radius (from its area) the section's radius `rho` less the rim's drawn half width.
void expectTumourSection(const UltrasoundImage& image, const UltrasoundImageModel& m, const KDL::Vector& section,
                         double rho, const std::string& what) {
  KDL::Vector sum;
  int count = 0;
  for (int r = 0; r < image.height; ++r) {
    for (int c = 0; c < image.width; ++c) {
      if (image.at(c, r) != grey(m.tumour_echo)) continue;
      sum += centreOf(image, c, r);
      ++count;
    }
  }
  ASSERT_GT(count, 0) << what << ": no tumour in the image";
  const KDL::Vector centre = imageXY(image, section);
  EXPECT_NEAR(centre.z(), 0.0, 1e-12) << what << ": the section's centre lies in the image plane";
  EXPECT_NEAR(sum.x() / count, centre.x(), image.spacing_x) << what;
  EXPECT_NEAR(sum.y() / count, centre.y(), image.spacing_y) << what;
  const double inner = std::sqrt(count * image.spacing_x * image.spacing_y / std::numbers::pi);
  EXPECT_NEAR(inner, rho - drawnHalf(m, m.rim_thickness), 0.5 * image.spacing_x) << what;
}

TEST(UltrasoundImage, TheTumourIsAHypoechoicDiscWhereThePlaneCutsItsSphere) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const double off = 0.006;  // m: the vertical plane y = off cuts the 12 mm tumour at (0, 0, -0.06)
  const KDL::Vector section(0.0, off, -0.06);  // the centre of the section: the sphere's centre moved into the plane
  const KDL::Frame probe = probeLookingAt({0.035, off, -0.001}, section, {-1, 0, 0});
  auto image = std::make_unique<UltrasoundImage>();
  const UltrasoundImageModel m = flatModel();
  UltrasoundImager(m, phantom, 1).render(probe, nullptr, *image);

  const double rho = std::sqrt(phantom.tumour_radius * phantom.tumour_radius - off * off);  // 10.4 mm
  expectTumourSection(*image, m, section, rho, "plane y = 6 mm");
  // The rim is bright: rho from the centre, deeper along the beam and to either side.
  for (const KDL::Vector& direction : {probe.M.UnitZ(), probe.M.UnitX(), -probe.M.UnitX()}) {
    const auto [c, r] = pixelOf(*image, section + direction * rho);
    EXPECT_TRUE(anyNear(*image, c, r, 1, 1, grey(m.rim_echo))) << "rim at pixel " << c << "," << r;
  }

  // With speckle and attenuation the disc still reads darker than the kidney beside it.
  UltrasoundImager(UltrasoundImageModel{}, phantom, 1).render(probe, nullptr, *image);
  const auto [cc, cr] = pixelOf(*image, section);
  const int aside = static_cast<int>(1.5 * rho / image->spacing_x);
  double inside = 0.0, beside = 0.0;
  for (int k = -4; k <= 4; ++k) {
    inside += image->at(cc + k, cr);
    beside += image->at(cc + aside + k, cr);
  }
  EXPECT_LT(inside, 0.5 * beside);

  // A plane that misses the sphere shows no tumour.
  UltrasoundImager(m, phantom, 1).render(probeLookingAt({0.035, 0.013, -0.001}, {0.0, 0.013, -0.06}, {-1, 0, 0}),
                                         nullptr, *image);
  for (std::size_t i = 0; i < std::size_t{image->width} * image->height; ++i) ASSERT_NE(image->pixels[i], grey(m.tumour_echo));
}

TEST(UltrasoundImage, TheTumourSectionIsRightForSeededRandomPlanes) {
  auto phantom = cobra::sim::loadScenario(kPhantom);
  phantom.forbidden.clear();  // no rib shadow over the tumour
  const UltrasoundImageModel m = flatModel();
  const UltrasoundImager imager(m, phantom, 4);
  auto image = std::make_unique<UltrasoundImage>();
  std::mt19937_64 random(2026);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double radius = phantom.tumour_radius;
  for (int sample = 0; sample < 12; ++sample) {
    // Array along a random horizontal direction, beam tilted up to 30 deg from the vertical within
    // the plane, the plane at a random distance h (|h| < 0.7 R) from the tumour's centre.
    const double yaw = 2.0 * std::numbers::pi * unit(random), tilt = (unit(random) - 0.5) * std::numbers::pi / 3.0;
    const double h = (2.0 * unit(random) - 1.0) * 0.7 * radius;
    const KDL::Vector along(std::cos(yaw), std::sin(yaw), 0.0);
    const KDL::Vector beam = along * std::sin(tilt) + KDL::Vector(0, 0, -1) * std::cos(tilt);
    const KDL::Vector array = along * std::cos(tilt) + KDL::Vector(0, 0, 1) * std::sin(tilt);
    const KDL::Vector normal = beam * array;
    const KDL::Vector section = phantom.tumour_center - normal * h;
    const KDL::Frame probe(KDL::Rotation(array, normal, beam), section - beam * ((section.z() + 0.001) / beam.z()));
    ASSERT_NEAR(probe.p.z(), -0.001, 1e-12);
    imager.render(probe, nullptr, *image);
    expectTumourSection(*image, m, section, std::sqrt(radius * radius - h * h), "sample " + std::to_string(sample));
  }
}

TEST(UltrasoundImage, LayerInterfacesLieAtThePhantomsDepths) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const UltrasoundImageModel m = flatModel();
  // Beam straight down from a face 0.3 mm in, array along x, away from the tumour, rib and vessel.
  const double face = 0.0003;
  const KDL::Frame probe(KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(0.0, -0.045, -face));
  auto image = std::make_unique<UltrasoundImage>();
  UltrasoundImager(m, phantom, 3).render(probe, nullptr, *image);
  const int column = image->width / 2;
  const double bottoms[] = {0.0, 0.002, 0.017, 0.032, 0.092};  // m: the skin's top and each layer's bottom (phantom.txt)
  auto rowAt = [&](double depth) { return static_cast<int>(std::floor((depth - face) / m.spacing_y)); };
  for (int i = 1; i < 5; ++i) {
    EXPECT_EQ(image->at(column, rowAt(bottoms[i])), grey(m.interface_echo)) << "boundary " << bottoms[i] << " m below the skin";
  }
  for (int layer = 0; layer < 4; ++layer) {
    const double middle = 0.5 * (bottoms[layer] + bottoms[layer + 1]);
    const std::string& name = phantom.layers[layer].tissue.name;
    EXPECT_EQ(image->at(column, rowAt(middle)), grey(layerEcho(m, name))) << name;
  }
  EXPECT_EQ(image->at(column, rowAt(0.097)), grey(m.deep_echo)) << "below the last layer";
  // One bright run down the column per boundary, none between them (the skin's top is above the face).
  int runs = 0;
  for (int r = 0; r < image->height; ++r) {
    const bool bright = image->at(column, r) == grey(m.interface_echo);
    if (bright && (r == 0 || image->at(column, r - 1) != grey(m.interface_echo))) ++runs;
  }
  EXPECT_EQ(runs, 4) << "the skin's bottom, fat/muscle, muscle/kidney, the kidney's bottom";
  // Attenuation darkens with depth: the kidney at its top and bottom, with the default model.
  UltrasoundImageModel speckle_free;
  speckle_free.speckle = 0.0;
  UltrasoundImager(speckle_free, phantom, 3).render(probe, nullptr, *image);
  const double kidney_top_gain = std::exp(-speckle_free.attenuation * (rowAt(0.034) + 0.5) * m.spacing_y);
  EXPECT_EQ(image->at(column, rowAt(0.034)), std::lround(255.0 * layerEcho(m, "kidney") * kidney_top_gain));
  EXPECT_LT(image->at(column, rowAt(0.09)), image->at(column, rowAt(0.034)));
}

TEST(UltrasoundImage, TheNeedleIsABrightLineInPlaneAndNoLineWhenThePlaneIsTurned) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const Needle needle;
  const KDL::Frame tip = needle.tip(), probe = needle.probe();
  auto with = std::make_unique<UltrasoundImage>(), without = std::make_unique<UltrasoundImage>();
  if (const char* path = std::getenv("COBRA_US_IMAGE_PGM")) {
    UltrasoundImager(UltrasoundImageModel{}, phantom, 11).render(probe, &tip, *with);
    writePgm(*with, path);
  }
  const UltrasoundImageModel m = flatModel();
  const UltrasoundImager imager(m, phantom, 11);
  imager.render(probe, &tip, *with);
  imager.render(probe, nullptr, *without);

  // Every point of the needle below the skin and inside the field of view is a needle pixel.
  const KDL::Vector entry = imageXY(*with, needle.entry), end = imageXY(*with, needle.target);
  EXPECT_NEAR(entry.z(), 0.0, 1e-9);
  EXPECT_NEAR(end.z(), 0.0, 1e-9);
  int along = 0;
  for (int k = 1; k <= 40; ++k) {
    const KDL::Vector p = needle.entry + (needle.target - needle.entry) * (k / 40.0);
    const auto [c, r] = pixelOf(*with, p);
    if (c < 0 || c >= with->width || r < 0 || r >= with->height || without->at(c, r) == 0) continue;  // out of view
    EXPECT_EQ(with->at(c, r), grey(m.needle_echo)) << "needle point " << k << "/40 at pixel " << c << "," << r;
    ++along;
  }
  EXPECT_GE(along, 30) << "the needle's path crosses the image";
  // ... and nothing else changed: every differing pixel is on the needle's projection.
  const double diagonal = std::hypot(m.spacing_x, m.spacing_y);
  const double reach = std::max(0.5 * m.needle_width, 0.5 * diagonal) + 1e-9;  // the drawn half width
  int changed = 0;
  for (int r = 0; r < with->height; ++r) {
    for (int c = 0; c < with->width; ++c) {
      if (with->at(c, r) == without->at(c, r)) continue;
      ++changed;
      const KDL::Vector p = centreOf(*with, c, r), d = end - entry;
      const double t = std::clamp(KDL::dot(p - entry, d) / KDL::dot(d, d), 0.0, 1.0);
      EXPECT_LE((p - (entry + d * t)).Norm(), reach) << "pixel " << c << "," << r;
    }
  }
  EXPECT_GE(changed, along);

  // The plane turned 90 deg about the beam crosses the needle at its tip only: at most the
  // shaft's section there (within a few mm of the tip), no line.
  const KDL::Frame turned = probe * KDL::Frame(KDL::Rotation::RotZ(std::numbers::pi / 2));
  imager.render(turned, &tip, *with);
  imager.render(turned, nullptr, *without);
  const KDL::Vector tip_xy = imageXY(*with, needle.target);
  changed = 0;
  for (int r = 0; r < with->height; ++r) {
    for (int c = 0; c < with->width; ++c) {
      if (with->at(c, r) == without->at(c, r)) continue;
      ++changed;
      const double mm = (centreOf(*with, c, r) - KDL::Vector(tip_xy.x(), tip_xy.y(), 0.0)).Norm() * 1000.0;
      EXPECT_LT(mm, 4.0) << "pixel " << c << "," << r << " changed by the needle " << mm << " mm from its tip";
    }
  }
  EXPECT_LT(changed, along / 3) << "a section, not a line";
  // Moved 3 mm off the plane (beam width 2 mm), the needle disappears; so it does tilted by 0.1 rad
  // about its tip with its shaft further off (its axis crosses the plane beyond the tip only).
  imager.render(probe, nullptr, *without);
  const KDL::Frame away = KDL::Frame(probe.M.UnitY() * 0.003) * tip;
  imager.render(probe, &away, *with);
  EXPECT_EQ(with->pixels, without->pixels);
  KDL::Frame tilted = away * KDL::Frame(KDL::Rotation::RotX(0.1));
  if (KDL::dot(tilted.M.UnitZ(), probe.M.UnitY()) > 0.0) tilted = away * KDL::Frame(KDL::Rotation::RotX(-0.1));
  imager.render(probe, &tilted, *with);
  EXPECT_EQ(with->pixels, without->pixels);
}

TEST(UltrasoundImage, NothingAboveTheSkinNorOutsideTheFieldOfView) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const UltrasoundImageModel m;
  const UltrasoundImager imager(m, phantom, 5);
  auto image = std::make_unique<UltrasoundImage>();
  // Pressed 1 mm in at the centre, rocked 25 deg along the array: one edge of the face in the air.
  const KDL::Frame probe =
      KDL::Frame(KDL::Vector(0.0, -0.04, -0.001)) * KDL::Frame(KDL::Rotation::RotX(std::numbers::pi) * KDL::Rotation::RotY(0.44));
  imager.render(probe, nullptr, *image);
  int lit = 0, in_air = 0, outside_view = 0;
  for (int c = 0; c < image->width; ++c) {
    for (int r = 0; r < image->height; ++r) {
      const KDL::Vector p = pointOf(*image, c, r), u = probe.Inverse(p);
      const bool outside = std::abs(u.x()) > m.array_half_width + u.z() * std::tan(m.half_sector);
      in_air += p.z() > 0.0;
      outside_view += outside;
      if (p.z() > 0.0 || outside) {
        EXPECT_EQ(image->at(c, r), 0) << "pixel " << c << "," << r << (outside ? " outside the field of view" : " in the air");
      } else {
        lit += image->at(c, r) > 0;
      }
    }
  }
  EXPECT_GT(in_air, 50) << "the rocked face's image reaches above the skin at one edge";
  EXPECT_GT(outside_view, 500) << "the top corners are outside the sector";
  EXPECT_GT(lit, image->width * image->height / 2);
  // Seeded random poses: pressed 0-3 mm in, anywhere within 3 cm, tilted up to 40 deg any way.
  std::mt19937_64 random(77);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int sample = 0; sample < 12; ++sample) {
    const KDL::Frame pose(KDL::Rotation::RotZ(std::numbers::pi * unit(random)) *
                              KDL::Rotation::RotX(std::numbers::pi + 0.7 * unit(random)) *
                              KDL::Rotation::RotZ(std::numbers::pi * unit(random)),
                          KDL::Vector(0.03 * unit(random), 0.03 * unit(random), -0.0015 * (1.0 + unit(random))));
    imager.render(pose, nullptr, *image);
    int shown = 0;
    for (int c = 0; c < image->width; ++c) {
      for (int r = 0; r < image->height; ++r) {
        const KDL::Vector p = pointOf(*image, c, r), u = pose.Inverse(p);
        if (p.z() > 0.0 || std::abs(u.x()) > m.array_half_width + u.z() * std::tan(m.half_sector)) {
          ASSERT_EQ(image->at(c, r), 0) << "sample " << sample << " pixel " << c << "," << r;
        }
        shown += image->at(c, r) > 0;
      }
    }
    EXPECT_GT(shown, image->width * image->height / 4) << "sample " << sample;
  }
  // Held 5 mm above the skin, the probe sees nothing.
  imager.render(KDL::Frame(KDL::Rotation::RotX(std::numbers::pi), KDL::Vector(0.0, -0.04, 0.005)), nullptr, *image);
  for (std::size_t i = 0; i < std::size_t{image->width} * image->height; ++i) ASSERT_EQ(image->pixels[i], 0);
}

TEST(UltrasoundImage, RibsShadowWhatLiesBelowVesselsAreDark) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const UltrasoundImageModel m = flatModel();
  auto image = std::make_unique<UltrasoundImage>();
  // Across the rib (axis along x at y = 0.03, 20 mm deep, radius 6 mm): array along y, beam down.
  const KDL::Frame across_rib = probeLookingAt({0.0, 0.03, -0.0005}, {0.0, 0.03, -0.1}, {0, 1, 0});
  UltrasoundImager(m, phantom, 2).render(across_rib, nullptr, *image);
  const auto [c, r] = pixelOf(*image, {0.0, 0.03, -0.0145});  // just inside the rib's top
  EXPECT_EQ(image->at(c, r), grey(m.bone_echo));
  const int deep = pixelOf(*image, {0.0, 0.03, -0.05}).second;  // the kidney, 50 mm down
  EXPECT_EQ(image->at(c, deep), grey(layerEcho(m, "kidney") * m.shadow)) << "the kidney in the rib's shadow";
  EXPECT_EQ(image->at(c + static_cast<int>(0.012 / image->spacing_x), deep), grey(layerEcho(m, "kidney")))
      << "the kidney beside the shadow";
  EXPECT_EQ(image->at(c, r - static_cast<int>(0.002 / image->spacing_y)), grey(layerEcho(m, "fat"))) << "the fat above the rib";

  // Through the vessel's centre (sphere at 0.02, -0.02, -0.07, radius 4 mm).
  const KDL::Frame through_vessel = probeLookingAt({0.02, -0.02, -0.0005}, {0.02, -0.02, -0.1}, {1, 0, 0});
  UltrasoundImager(m, phantom, 2).render(through_vessel, nullptr, *image);
  const auto [vc, vr] = pixelOf(*image, {0.02, -0.02, -0.07});
  EXPECT_EQ(image->at(vc, vr), grey(m.vessel_echo));
  const int wall = pixelOf(*image, {0.02, -0.02, -0.066}).second;
  EXPECT_TRUE(anyNear(*image, vc, wall, 0, 1, grey(m.rim_echo))) << "its wall";
  EXPECT_EQ(image->at(vc, pixelOf(*image, {0.02, -0.02, -0.078}).second), grey(layerEcho(m, "kidney")))
      << "no shadow below a vessel";
}

TEST(UltrasoundImage, TheSameSeedGivesTheSameImageAnotherSeedOtherSpeckle) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const Needle needle;
  const KDL::Frame tip = needle.tip(), probe = needle.probe();
  auto a = std::make_unique<UltrasoundImage>(), b = std::make_unique<UltrasoundImage>();
  UltrasoundImager(UltrasoundImageModel{}, phantom, 42).render(probe, &tip, *a);
  UltrasoundImager(UltrasoundImageModel{}, phantom, 42).render(probe, &tip, *b);
  EXPECT_EQ(a->pixels, b->pixels);
  UltrasoundImager(UltrasoundImageModel{}, phantom, 43).render(probe, &tip, *b);
  int differ = 0;
  for (std::size_t i = 0; i < std::size_t{a->width} * a->height; ++i) differ += a->pixels[i] != b->pixels[i];
  EXPECT_GT(differ, a->width * a->height / 3);
}

TEST(UltrasoundImage, RenderingAllocatesNothingAndFillsTheGeometry) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  UltrasoundImageModel m;
  m.width = 200;
  m.height = 100;
  m.spacing_x = 0.0004;
  const Needle needle;
  const KDL::Frame tip = needle.tip(), probe = needle.probe();
  const UltrasoundImager imager(m, phantom, 9);
  auto image = std::make_unique<UltrasoundImage>();
  EXPECT_EQ(cobra::test_support::allocationsDuring([&] { imager.render(probe, &tip, *image); }), 0);
  EXPECT_EQ(image->width, 200);
  EXPECT_EQ(image->height, 100);
  EXPECT_DOUBLE_EQ(image->spacing_x, 0.0004);
  EXPECT_DOUBLE_EQ(image->spacing_y, m.spacing_y);
  // Frame I: x along the array, y along the beam, the corner half the width to the array's -x side.
  EXPECT_LT((image->pose.M.UnitX() - probe.M.UnitX()).Norm(), 1e-12);
  EXPECT_LT((image->pose.M.UnitY() - probe.M.UnitZ()).Norm(), 1e-12);
  EXPECT_LT((image->pose.p - (probe.p - probe.M.UnitX() * 0.04)).Norm(), 1e-12);
}

TEST(UltrasoundImage, BandsOfColumnsMakeTheWholeImageBitForBit) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  const Needle needle;
  const KDL::Frame tip = needle.tip();
  const UltrasoundImager imager(UltrasoundImageModel{}, phantom, 5);
  auto whole = std::make_unique<UltrasoundImage>(), banded = std::make_unique<UltrasoundImage>();
  // The needle in plane, and across the rib (its shadow runs down each column).
  for (const KDL::Frame& probe : {needle.probe(), probeLookingAt({0.0, 0.03, -0.0005}, {0.0, 0.03, -0.1}, {0, 1, 0})}) {
    imager.render(probe, &tip, *whole);
    banded->pixels.fill(17);
    // Bands of uneven widths, the last one past the image's edge (clamped).
    int first = 0;
    for (const int band : {1, 16, 5, 60, 100}) {
      EXPECT_EQ(cobra::test_support::allocationsDuring([&] { imager.renderColumns(probe, &tip, *banded, first, first + band); }),
                0);
      first += band;
    }
    const auto pixels = static_cast<std::ptrdiff_t>(whole->width) * whole->height;
    EXPECT_TRUE(std::equal(whole->pixels.begin(), whole->pixels.begin() + pixels, banded->pixels.begin()));
    EXPECT_EQ(banded->pose, whole->pose);
    EXPECT_EQ(banded->width, whole->width);
  }
  // A band leaves the other columns as they were, lifted off the skin too (its columns black).
  const auto onlyTheBand = [&](const KDL::Frame& probe) {
    imager.render(probe, &tip, *whole);
    banded->pixels.fill(17);
    imager.renderColumns(probe, &tip, *banded, 60, 70);
    for (int r = 0; r < banded->height; ++r) {
      for (int c = 0; c < banded->width; ++c) {
        if (banded->at(c, r) != (c < 60 || c >= 70 ? 17 : whole->at(c, r)))
          return ::testing::AssertionFailure() << "pixel " << c << ", " << r;
      }
    }
    return ::testing::AssertionSuccess();
  };
  EXPECT_TRUE(onlyTheBand(needle.probe()));
  EXPECT_TRUE(onlyTheBand(KDL::Frame(KDL::Vector(0, 0, 0.01))));
}

TEST(UltrasoundImage, ParametersOutOfRangeAreRefusedByName) {
  const auto phantom = cobra::sim::loadScenario(kPhantom);
  UltrasoundImageModel m;
  m.width = 300;
  EXPECT_EQ(cobra::test_support::messageOf([&] { UltrasoundImager(m, phantom, 0); }),
            "ultrasound image: width = 300, expected in [1, 256] px");
  m = UltrasoundImageModel{};
  m.layer_echo.emplace_back("liver", 1.5);
  EXPECT_EQ(cobra::test_support::messageOf([&] { UltrasoundImager(m, phantom, 0); }),
            "ultrasound image: layer_echo[liver] = 1.5, expected in [0, 1]");
  m = UltrasoundImageModel{};
  m.beam_width = 0.0;
  EXPECT_EQ(cobra::test_support::messageOf([&] { UltrasoundImager(m, phantom, 0); }),
            "ultrasound image: beam_width = 0, expected > 0 m");
}

}  // namespace
