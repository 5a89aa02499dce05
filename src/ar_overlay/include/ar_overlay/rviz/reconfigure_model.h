// The tracking panel's view of one dynamic_reconfigure server, without Qt: the
// groups and parameters of its ConfigDescription, current values from a Config,
// and the one-parameter Config a widget sends to <server>/set_parameters. The
// panel is generic on purpose: it reads pose_ekf's and cone_tracker's parameter
// names from their servers, so it needs neither package to build and follows
// their .cfg files as they change.
#pragma once

#include <dynamic_reconfigure/Config.h>
#include <dynamic_reconfigure/ConfigDescription.h>

#include <string>
#include <vector>

namespace ar_overlay {

enum class ParamKind { kBool, kInt, kDouble, kString };

struct ParamSpec {
  std::string name, description;
  ParamKind kind = ParamKind::kDouble;
  double min = 0, max = 0, default_value = 0;  // numbers and bools (0/1); unused for strings
  std::string default_string;
};

struct ParamGroupSpec {
  std::string name;  // "Default" is the .cfg's top level
  std::vector<ParamSpec> params;
};

// Groups in the description's order; groups without parameters are left out.
// Parameters of an unknown type are skipped and named in *skipped (if given).
std::vector<ParamGroupSpec> GroupsFromDescription(const dynamic_reconfigure::ConfigDescription& description,
                                                  std::vector<std::string>* skipped = nullptr);

// The value of `name` in a Config (bools as 0/1); false when it is not there.
bool NumberFromConfig(const dynamic_reconfigure::Config& config, const std::string& name, double* value);
bool StringFromConfig(const dynamic_reconfigure::Config& config, const std::string& name, std::string* value);

// A Config holding only this parameter, the request for set_parameters (the
// server keeps every other value). Numbers are clamped to [min, max]; ints are
// rounded. A NaN number throws std::invalid_argument naming the parameter.
dynamic_reconfigure::Config SingleParameter(const ParamSpec& spec, double value);
dynamic_reconfigure::Config SingleParameter(const ParamSpec& spec, const std::string& value);

}  // namespace ar_overlay
