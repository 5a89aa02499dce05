// The cone layout: where the cones stand in the `cones` frame {M} (origin at the centroid of the
// cone bases, z up, x toward cone 1; DESIGN.md), and the scenery the simulator draws around them.
// One schema and one parser for the tracker, the simulator and the rig (config/layouts/*.yaml):
//
//   equilateral: {side_m: 1.5, height_m: 0.71, style: road}   # 3 cones, cone 1 on +x (3.1.3)
//   cones:                                                    # and/or explicit cones
//     - {x_m: 1.0, y_m: 0.0, z_m: 0.0, height_m: 0.71, style: road, tau: 0.142857,
//        albedo: [r, g, b], collars: [[from, to], ...], base_plate_m: 0.355}
//   boxes:     [{x_m, y_m, yaw_deg, sx_m, sy_m, sz_m, albedo}]   # orange things that are not cones
//   patches:   [{x_m, y_m, yaw_deg, sx_m, sy_m, albedo}]
//   people:    [{x_m, y_m, height_m}]
//   platforms: [{x_m, y_m, yaw_deg, sx_m, sy_m, sz_m, albedo, rows, cols, spacing_m, dot_radius_m, dot_albedo}]
//   ground: asphalt | grass | concrete
//
// Unknown or misspelt keys are refused (strict_yaml.h). ROS-free.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace rig_model {

// What every layout must satisfy: 3 to 30 cones of 4" to 36" (0.10 to 0.92 m).
struct LayoutLimits {
  static constexpr int kMinCones = 3;
  static constexpr int kMaxCones = 30;
  static constexpr double kMinHeightM = 0.10;  // 4" indoor cone
  static constexpr double kMaxHeightM = 0.92;  // 36" road cone
};

enum class ConeStyle { kPlain, kRoad };

// A cone standing upright; a stacked cone simply has its base above the ground.
struct ConeSpec {
  Eigen::Vector3d base_m = Eigen::Vector3d::Zero();  // centre of the base circle
  double height_m = 0.71;
  double tau = 1.0 / 7.0;  // radius-to-height ratio (3.1.4)
  ConeStyle style = ConeStyle::kRoad;
  // White reflective bands, as (from, to) fractions of the height above the base.
  std::vector<std::pair<double, double>> collars;
  Eigen::Vector3d albedo = Eigen::Vector3d(0.90, 0.16, 0.012);  // linear RGB, safety orange
  double base_plate_m = 0.0;  // side of the black square base on the ground (road cones)
  // A surveyed position's 1-sigma per axis (`sigma_m`, surveyed_layout.h); NaN when not given.
  Eigen::Vector3d sigma_m = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());

  double radius_m() const { return tau * height_m; }
  Eigen::Vector3d peak_m() const { return base_m + Eigen::Vector3d(0, 0, height_m); }
  Eigen::Vector3d mid_m() const { return base_m + Eigen::Vector3d(0, 0, 0.5 * height_m); }
};

// The peak, mid and base model points (3.12) of a cone, moved to its surface on the side facing
// the centre of projection (3.1.4): the silhouette's mid and base points lie on the front of the
// cone, radius tau * (height above) off its axis, toward the camera in the base plane (3.16)
// (3.17) (3.18). The one definition the tracker's pose and the EKF's per-cone update share.
std::array<Eigen::Vector3d, 3> CorrectedModelPoints(const Eigen::Vector3d& base_m, double height_m, double tau,
                                                    const Eigen::Vector3d& p_camera_in_cones_m);

// Orange things that are not cones, to test the segmenter honestly.
struct BoxSpec {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  Eigen::Vector3d size_m = Eigen::Vector3d(0.4, 0.3, 0.3);
  Eigen::Vector3d albedo = Eigen::Vector3d(0.85, 0.18, 0.02);
};
struct PatchSpec {  // flat, on the ground
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  Eigen::Vector2d size_m = Eigen::Vector2d(0.5, 0.5);
  Eigen::Vector3d albedo = Eigen::Vector3d(0.85, 0.18, 0.02);
};
struct PersonSpec {  // a standing person in a hi-vis orange vest, as a cylinder
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double height_m = 1.75;
  double radius_m = 0.22;
};

// The overlay test platform (7.2): a white board on the ground whose top face carries a rows x cols
// grid of blue dots, centred on the board.
struct PlatformSpec {
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  Eigen::Vector3d size_m = Eigen::Vector3d(0.6, 0.6, 0.05);  // the board stands on the ground
  Eigen::Vector3d albedo = Eigen::Vector3d(0.80, 0.80, 0.78);
  int rows = 5, cols = 5;  // along the board's y and x
  double spacing_m = 0.1, dot_radius_m = 0.02;
  Eigen::Vector3d dot_albedo = Eigen::Vector3d(0.02, 0.08, 0.60);
  // Dot centres on the top face in {M}, row-major (row along y, column along x).
  std::vector<Eigen::Vector3d> DotCentres() const;
};

enum class GroundStyle { kAsphalt, kGrass, kConcrete };

struct Layout {
  std::vector<ConeSpec> cones;  // file order: the equilateral cones first, then `cones:`
  std::vector<BoxSpec> boxes;
  std::vector<PatchSpec> patches;
  std::vector<PersonSpec> people;
  std::vector<PlatformSpec> platforms;
  GroundStyle ground = GroundStyle::kAsphalt;

  // Centroid of the cone bases (the origin of {M} for a well-formed layout).
  Eigen::Vector3d ConeCentroid() const;
};

// A cone of the given height and style with the collars such a cone carries.
ConeSpec MakeCone(const Eigen::Vector3d& base_m, double height_m, ConeStyle style);
// The thesis's layout (3.1.3): three identical cones in an equilateral triangle, centred on the
// origin, cone 1 on +x.
Layout EquilateralLayout(double side_m, double height_m, ConeStyle style);
// Three 28" (0.71 m) road cones, 1.5 m apart (config/layouts/default.yaml).
Layout DefaultLayout();

// Reads a layout file. Throws FileError (strict_yaml.h) naming the file, the line and the field:
// "cones.yaml:7: unknown key 'cones[0].hieght_m' (did you mean 'height_m'?)",
// "cones.yaml:3: cones[1].height_m: 1.2 is outside [0.1, 0.92] m".
Layout LoadLayoutFile(const std::string& path);
// The same on YAML text; `source` names it in messages.
Layout ParseLayout(const std::string& yaml_text, const std::string& source);

}  // namespace rig_model
