// What people look at: the debug image (the frame with the classified mask
// tinted, blobs, peak/mid/base, ids and gate outcomes; rviz's colour-mask
// preview) and the layout as rviz markers.
#pragma once

#include <string>
#include <vector>

#include <sensor_msgs/Image.h>
#include <visualization_msgs/MarkerArray.h>

#include "cone_tracker/node/tracker_adapter.h"

namespace cone_tracker {

// bgr8, same size and header as the input. mask: the segmenter's full-size
// mask of this frame (nonzero = cone pixel), ignored when its size is wrong.
// Returns null when the image cannot be converted.
sensor_msgs::ImagePtr MakeDebugImage(const sensor_msgs::ImageConstPtr& image, const std::vector<uint8_t>& mask,
                                     const FrameResult& result, const DebugImageConfig& config);

// One orange cone mesh and one id label per layout cone, in frame_id.
visualization_msgs::MarkerArray MakeLayoutMarkers(const std::vector<ConeModel>& layout, const std::string& frame_id);

}  // namespace cone_tracker
