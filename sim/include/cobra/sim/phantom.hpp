#pragma once
/// @file
/// The abdomen phantom of the puncturing task (thesis §4.2): tissue layers below the skin, a
/// spherical tumour, forbidden regions (ribs, vessels), and a small text format to describe it.
///
/// Frame P (phantom): the undeformed skin is the plane z = 0 with tissue below it (z < 0); the
/// depth of a point is -z (m). Layers are stacked from the skin downwards in the order given.

#include <string>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

namespace cobra::sim {

/// Mechanical properties of one tissue (a layer or the tumour). The force model is in
/// needle_tissue.hpp; values of the default abdomen state their sources.
struct TissueProperties {
  std::string name;                 ///< "skin", "fat", ...
  double puncture_force = 1.0;      ///< N, > 0: the membrane force at which it ruptures
  double k1 = 300.0;                ///< N/m, >= 0: linear membrane stiffness before puncture
  double k2 = 1.0e5;                ///< N/m², >= 0: quadratic membrane stiffness before puncture
  double cutting_force = 0.3;       ///< N, >= 0: resistance of the tip cutting through it (advancing only)
  double coulomb_friction = 5.0;    ///< N/m, >= 0: Coulomb friction per metre of shaft inside it
  double viscous_friction = 50.0;   ///< N·s/m², >= 0: viscous friction per metre of shaft, per m/s
  double lateral_stiffness = 500.0; ///< N/m, >= 0: restoring force per metre of tip offset from the channel
};

/// A layer of tissue of a given thickness below the previous one.
struct TissueLayer {
  TissueProperties tissue;
  double thickness = 0.01;  ///< m, > 0
};

/// A forbidden region: a capsule (segment a-b swept by radius; a == b gives a sphere), frame P.
struct ForbiddenRegion {
  std::string name;                   ///< "rib", "vessel", ...
  KDL::Vector a, b;                   ///< m, the capsule's axis end points
  double radius = 0.005;              ///< m, > 0
};

/// Everything the needle can meet.
struct PhantomScenario {
  std::vector<TissueLayer> layers;    ///< skin first; at least one
  TissueProperties tumour_tissue;     ///< the tumour's properties
  KDL::Vector tumour_center{0, 0, -0.05};  ///< m, frame P
  double tumour_radius = 0.01;        ///< m, > 0
  std::vector<ForbiddenRegion> forbidden;
  double penalty_stiffness = 1.0e5;   ///< N/m, > 0: force per metre of penetration into a forbidden region
};

/// An abdomen of skin, fat, muscle and kidney with a tumour in the kidney (values documented in
/// phantom.cpp, each with its source or marked as an assumption), a rib and a vessel.
PhantomScenario defaultAbdomen();

/// @throws std::invalid_argument naming the layer/region, the parameter and the expected range.
void validate(const PhantomScenario& scenario);

/// Parses the scenario text format (one statement per line, `#` starts a comment):
///
///     layer NAME thickness=M [puncture_force=N k1=.. k2=.. cutting_force=.. coulomb_friction=..
///                             viscous_friction=.. lateral_stiffness=..]
///     tumour center=X,Y,Z radius=M [same tissue keys]
///     sphere NAME center=X,Y,Z radius=M          (forbidden)
///     capsule NAME a=X,Y,Z b=X,Y,Z radius=M      (forbidden)
///     penalty_stiffness VALUE
///
/// Units: m, N, N/m, N/m², N·s/m² as in TissueProperties. Keys left out keep the defaults of
/// TissueProperties. `source` names the text in errors.
/// @throws std::invalid_argument "SOURCE:LINE: message" for syntax errors, unknown statements or
/// keys and values out of range.
PhantomScenario parseScenario(std::string_view text, std::string_view source);
/// Reads and parses `path`. @throws std::invalid_argument naming the path when it cannot be read.
PhantomScenario loadScenario(const std::string& path);

/// Depth (m) of the top of layer i; the bottom is top + thickness. Frame P.
double layerTop(const PhantomScenario& scenario, std::size_t layer) noexcept;

}  // namespace cobra::sim
