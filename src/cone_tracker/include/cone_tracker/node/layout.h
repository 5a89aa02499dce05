// The cone layout for the tracker: rig_model's layout file (the one schema and strict parser that
// the simulator, bag replay and the rig share, rig_model/layout.h) reduced to the cones' model
// points. The scenery in the file (boxes, patches, people, platforms, ground) is the simulator's.
// ROS-free.
#pragma once

#include <string>
#include <vector>

#include "cone_tracker/vision/cone_pose.h"
#include "rig_model/layout.h"

namespace cone_tracker {

// The layout schema's maximum: the search without a prediction tries every assignment up to 8
// cones and beyond uses pair hypotheses with bounded work (cone_pose_search.h).
constexpr int kMaxTrackedCones = rig_model::LayoutLimits::kMaxCones;

// Returns false with rig_model's message (file, line, field) or the tracker's limit; *cones
// untouched then.
bool LoadLayoutFile(const std::string& path, std::vector<ConeModel>* cones, std::string* error);
// The same on YAML text; `source` names it in messages.
bool ParseLayout(const std::string& yaml_text, const std::string& source, std::vector<ConeModel>* cones,
                 std::string* error);

}  // namespace cone_tracker
