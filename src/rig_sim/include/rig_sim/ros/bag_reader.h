// Reads the records the validator needs out of a bag.
#pragma once

#include <string>

#include "rig_sim/bag_checks.h"
#include "rig_sim/ros/messages.h"

namespace rig_sim {

// Topics are matched with or without a leading '/'. False with a message on I/O errors.
bool ReadBagContents(const std::string& path, const TopicNames& topics, BagContents* out, std::string* error);

}  // namespace rig_sim
