#include "cone_tracker/node/layout.h"

#include <functional>

#include "rig_model/strict_yaml.h"

namespace cone_tracker {
namespace {

bool Load(const std::function<rig_model::Layout()>& read, const std::string& source, std::vector<ConeModel>* cones,
          std::string* error) {
  try {
    std::vector<ConeModel> models = ConeModels(read());
    if (static_cast<int>(models.size()) > kMaxTrackedCones) {
      if (error)
        *error = "layout " + source + ": " + std::to_string(models.size()) + " cones; the tracker matches at most " +
                 std::to_string(kMaxTrackedCones);
      return false;
    }
    *cones = std::move(models);
    return true;
  } catch (const rig_model::FileError& e) {
    if (error) *error = std::string("layout ") + e.what();
  }
  return false;
}

}  // namespace

bool ParseLayout(const std::string& text, const std::string& source, std::vector<ConeModel>* cones,
                 std::string* error) {
  return Load([&] { return rig_model::ParseLayout(text, source); }, source, cones, error);
}

bool LoadLayoutFile(const std::string& path, std::vector<ConeModel>* cones, std::string* error) {
  return Load([&] { return rig_model::LoadLayoutFile(path); }, path, cones, error);
}

}  // namespace cone_tracker
