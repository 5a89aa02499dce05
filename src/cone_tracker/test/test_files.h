// What several cone_tracker tests share: the message of a thrown exception, and the project's data
// folder beside the repository (../shared/data, also from a worktree one level deeper).
#pragma once

#include <cstdlib>
#include <exception>
#include <fstream>
#include <functional>
#include <string>

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
// ../shared/data/<subdir> found from the package source, or the folder the environment variable env
// names; "" when neither holds probe_file (the test then skips).
inline std::string SharedDataDir(const std::string& subdir, const std::string& probe_file, const char* env) {
  if (const char* dir = std::getenv(env)) return dir;
  const std::string pkg = CONE_TRACKER_SOURCE_DIR;
  for (const char* up : {"/../..", "/../../.."})
    for (const char* shared : {"/../shared", "/../../shared"}) {
      const std::string dir = pkg + up + shared + "/data/" + subdir;
      if (std::ifstream(dir + "/" + probe_file)) return dir;
    }
  return "";
}
#endif

}  // namespace cone_tracker
