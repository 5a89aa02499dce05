// survey_layout's ROS side: a walk-around bag to the survey's input. Every frame is segmented with
// cone_tracker's segmenter (3.1.5); the camera model is the bag's camera_info, the camera-IMU
// rotation a calibration file or the bag's static tf camera -> imu.
#pragma once

#include <string>

#include "cone_survey/survey.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_survey {

struct BagInputOptions {
  std::string image_topic = "camera/image_raw";
  std::string info_topic = "camera/camera_info";
  std::string imu_topic = "imu/data_raw";
  std::string camera_imu_file;  // calibrate_camera_imu's YAML; "" takes the bag's /tf_static
  cone_tracker::SegmenterConfig segmenter;
};

// False with one line naming the bag and what is missing (camera_info, IMU, images, the camera-IMU
// rotation) or unreadable. *camera_imu_source says where the rotation came from.
bool ReadSurveyBag(const std::string& path, const BagInputOptions& options, SurveyInput* out,
                   std::string* camera_imu_source, std::string* error);

}  // namespace cone_survey
