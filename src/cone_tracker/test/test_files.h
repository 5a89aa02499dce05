// What several cone_tracker tests share: the message of a thrown exception, and the project's data
// folder beside the repository (../shared/data, also from a worktree one level deeper).
#pragma once

#include <exception>
#include <functional>
#include <string>

#include "rig_model/shared_data.h"

namespace cone_tracker {

// The what() of the exception f throws; "" when it throws none.
inline std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

#ifdef CONE_TRACKER_SOURCE_DIR  // set by the tests that read the data
// ../shared/data/<subdir> (rig_model/shared_data.h), or the folder the environment variable env names; "" when
// neither holds probe_file (the test then skips).
inline std::string SharedDataDir(const std::string& subdir, const std::string& probe_file, const char* env) {
  return rig_model::SharedDataDir(CONE_TRACKER_SOURCE_DIR, subdir, probe_file, env);
}
#endif

}  // namespace cone_tracker
