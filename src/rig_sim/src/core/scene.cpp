#include "rig_sim/scene.h"

#include "rig_model/strict_yaml.h"

namespace rig_sim {

bool ParseSceneYaml(const std::string& text, Scene* scene, std::string* error) {
  try {
    *scene = rig_model::ParseLayout(text, "layout");
    return true;
  } catch (const rig_model::FileError& e) {
    if (error) *error = e.what();
    return false;
  }
}

bool LoadSceneYaml(const std::string& path, Scene* scene, std::string* error) {
  try {
    *scene = rig_model::LoadLayoutFile(path);
    return true;
  } catch (const rig_model::FileError& e) {
    if (error) *error = e.what();
    return false;
  }
}

}  // namespace rig_sim
