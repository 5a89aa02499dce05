// rosrun cone_survey survey_layout --bag IN.bag --inventory INV.yaml --output LAYOUT.yaml [options]
// The first step of setting up a site: where the placed cones stand, from a walk around them.
#include <cstdio>
#include <fstream>
#include <string>

#include "cone_survey/ros/bag_input.h"
#include "cone_survey/survey.h"
#include "rig_model/strict_yaml.h"
#include "rig_model/surveyed_layout.h"

namespace {

void Usage() {
  std::printf(
      "usage: survey_layout --bag IN.bag --inventory INV.yaml --output LAYOUT.yaml [options]\n"
      "Surveys the placed cones from a walk around them (camera and IMU in the bag; hold the rig still for\n"
      "the first second) and writes their layout (rig_model's schema, each position's 1-sigma as sigma_m).\n\n"
      "options:\n"
      "  --camera-imu FILE     calibrate_camera_imu's YAML (default: the bag's /tf_static camera -> imu)\n"
      "  --image-topic T       default camera/image_raw\n"
      "  --camera-info-topic T default camera/camera_info\n"
      "  --imu-topic T         default imu/data_raw\n"
      "  --min-frames N        frames a cone must be seen in (default 30, at --adjust-rate-hz)\n"
      "  --min-spread-deg D    arc of directions a cone must be seen from (default 90)\n"
      "  --adjust-rate-hz F    frames per second the adjustment uses (default 10)\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string bag, inventory_file, output;
  cone_survey::BagInputOptions in_options;
  cone_survey::SurveyConfig config;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      Usage();
      return 0;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "survey_layout: %s needs a value (see --help)\n", a.c_str());
      return 2;
    }
    const std::string v = argv[++i];
    try {
      if (a == "--bag")
        bag = v;
      else if (a == "--inventory")
        inventory_file = v;
      else if (a == "--output" || a == "-o")
        output = v;
      else if (a == "--camera-imu")
        in_options.camera_imu_file = v;
      else if (a == "--image-topic")
        in_options.image_topic = v;
      else if (a == "--camera-info-topic")
        in_options.info_topic = v;
      else if (a == "--imu-topic")
        in_options.imu_topic = v;
      else if (a == "--min-frames")
        config.min_frames = std::stoi(v);
      else if (a == "--min-spread-deg")
        config.min_view_spread_deg = std::stod(v);
      else if (a == "--adjust-rate-hz")
        config.adjust_rate_hz = std::stod(v);
      else {
        std::fprintf(stderr, "survey_layout: unknown argument '%s' (see --help)\n", a.c_str());
        return 2;
      }
    } catch (const std::exception&) {
      std::fprintf(stderr, "survey_layout: bad value '%s' for %s\n", v.c_str(), a.c_str());
      return 2;
    }
  }
  if (bag.empty() || inventory_file.empty() || output.empty()) {
    std::fprintf(stderr, "survey_layout: --bag, --inventory and --output are required (see --help)\n");
    return 2;
  }
  const std::string bad_config = config.Validate();
  if (!bad_config.empty()) {
    std::fprintf(stderr, "survey_layout: %s\n", bad_config.c_str());
    return 2;
  }
  cone_survey::Inventory inventory;
  cone_survey::SurveyInput input;
  std::string error, camera_imu;
  try {
    inventory = cone_survey::LoadInventoryFile(inventory_file);
  } catch (const rig_model::FileError& e) {
    std::fprintf(stderr, "survey_layout: %s\n", e.what());
    return 2;
  }
  if (!cone_survey::ReadSurveyBag(bag, in_options, &input, &camera_imu, &error)) {
    std::fprintf(stderr, "survey_layout: %s\n", error.c_str());
    return 1;
  }
  std::printf("survey_layout: %zu frames, %zu IMU samples; camera-IMU rotation from %s\n", input.frames.size(),
              input.imu.size(), camera_imu.c_str());
  const cone_survey::SurveyResult r = cone_survey::SurveyLayout(input, inventory, config);
  for (const std::string& note : r.notes) std::printf("survey_layout: note: %s\n", note.c_str());
  if (!r.ok) {
    std::fprintf(stderr, "survey_layout: %s\n", r.error.c_str());
    return 1;
  }
  std::printf(
      "survey_layout: %d tracks, %d frames adjusted, %d observations; reprojection RMS %.2f px; detected bases %.2f px "
      "below the model's; scale sigma %.2f %%\n",
      r.tracks, r.frames_adjusted, r.observations, r.reprojection_rms_px, r.base_offset_px, 100.0 * r.scale_sigma);
  std::printf(
      "  cone                      x_m      y_m      z_m   sigma_xyz_mm        frames  spread_deg  rms_px  "
      "correlation\n");
  std::vector<rig_model::ConeSpec> cones;
  std::vector<Eigen::Vector3d> sigmas;
  for (size_t i = 0; i < r.cones.size(); ++i) {
    const cone_survey::SurveyedCone& c = r.cones[i];
    std::printf("  %-22s %8.3f %8.3f %8.3f   %4.1f %4.1f %4.1f   %6d  %10.0f  %6.2f  %11.1f\n",
                inventory.Name(static_cast<int>(i)).c_str(), c.spec.base_m.x(), c.spec.base_m.y(), c.spec.base_m.z(),
                1e3 * c.sigma_m.x(), 1e3 * c.sigma_m.y(), 1e3 * c.sigma_m.z(), c.frames, c.view_spread_deg, c.rms_px,
                c.correlation_factor);
    cones.push_back(c.spec);
    sigmas.push_back(c.sigma_m);
  }
  std::ofstream out(output);
  out << "# survey_layout --bag " << bag << " --inventory " << inventory_file << "\n"
      << "# frame: origin at " << inventory.Name(inventory.origin) << ", +x toward " << inventory.Name(inventory.x_axis)
      << ", z up; sigma_m: 1-sigma per axis in this frame\n"
      << "# reprojection RMS " << r.reprojection_rms_px << " px over " << r.observations << " sightings in "
      << r.frames_adjusted << " frames\n"
      << rig_model::ConesYaml(cones, sigmas);
  if (!out) {
    std::fprintf(stderr, "survey_layout: %s: cannot write\n", output.c_str());
    return 1;
  }
  std::printf("survey_layout: wrote %s\n", output.c_str());
  return 0;
}
