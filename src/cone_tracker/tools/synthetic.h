// Synthetic PnP cases shared by the tests, the experiments and the benchmark:
// the thesis's chapter 7.1 setup (fu = 770, fv = 776, 1024×768, points about
// 5 ft in front of the camera with a 1 ft spread) and the cone layout (three
// cones × peak/mid/base).
#pragma once
#include <Eigen/Core>
#include <random>
#include <vector>

#include "cone_tracker/pose/pnp.h"

namespace cone_tracker {
namespace sim {

struct Case {
  CameraModel camera;
  std::vector<Eigen::Vector3d> model;  // metres, {M}
  pose_math::Pose T_camera_model;      // truth
  std::vector<Eigen::Vector2d> image;  // noise-free pixels
};

CameraModel ThesisCamera();  // fu = 770, fv = 776, (512, 384), no distortion
constexpr double kFiveFeetM = 1.524;
constexpr double kOneFootM = 0.3048;

// A random rotation, points uniform in a 1 ft cube centred 5 ft in front of
// the camera (7.1).
Case RandomCloud(std::mt19937& rng, int points);
// Three 0.7 m cones on a 1 m circumradius triangle, points at each cone's peak,
// mid-height and base, seen from 3–5 m at 10–40° elevation.
Case ConeLayout(std::mt19937& rng);
// Pixels of the model at T (through cv::projectPoints when the camera has
// distortion). Returns false if a point is behind the camera.
bool Project(const CameraModel& camera, const pose_math::Pose& T, const std::vector<Eigen::Vector3d>& model,
             std::vector<Eigen::Vector2d>* image);
std::vector<Eigen::Vector2d> AddNoise(std::mt19937& rng, const std::vector<Eigen::Vector2d>& image, double sigma_px);
pose_math::Pose RandomRotationPose(std::mt19937& rng, const Eigen::Vector3d& t);

}  // namespace sim
}  // namespace cone_tracker
