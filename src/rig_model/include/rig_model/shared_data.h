// Where the project's real data lies: ../shared/data beside the repository (also from a worktree one level deeper).
// For the tests that read it and skip when it is absent; header-only.
#pragma once

#include <cstdlib>
#include <fstream>
#include <string>

namespace rig_model {

// ../shared/data/<subdir> found from a package's source folder, or the folder the environment variable env
// names; "" when neither holds probe_file.
inline std::string SharedDataDir(const std::string& package_source_dir, const std::string& subdir,
                                 const std::string& probe_file, const char* env) {
  if (const char* dir = std::getenv(env)) return dir;
  for (const char* up : {"/../..", "/../../.."})
    for (const char* shared : {"/../shared", "/../../shared"}) {
      const std::string dir = package_source_dir + up + shared + "/data/" + subdir;
      if (std::ifstream(dir + "/" + probe_file)) return dir;
    }
  return "";
}

}  // namespace rig_model
