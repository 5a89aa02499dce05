#include "ar_overlay/rviz/reconfigure_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ar_overlay {
namespace {

bool Kind(const std::string& type, ParamKind* kind) {
  if (type == "bool")
    *kind = ParamKind::kBool;
  else if (type == "int")
    *kind = ParamKind::kInt;
  else if (type == "double")
    *kind = ParamKind::kDouble;
  else if (type == "str")
    *kind = ParamKind::kString;
  else
    return false;
  return true;
}

}  // namespace

bool NumberFromConfig(const dynamic_reconfigure::Config& config, const std::string& name, double* value) {
  for (const auto& p : config.doubles)
    if (p.name == name) return *value = p.value, true;
  for (const auto& p : config.ints)
    if (p.name == name) return *value = p.value, true;
  for (const auto& p : config.bools)
    if (p.name == name) return *value = p.value ? 1.0 : 0.0, true;
  return false;
}

bool StringFromConfig(const dynamic_reconfigure::Config& config, const std::string& name, std::string* value) {
  for (const auto& p : config.strs)
    if (p.name == name) return *value = p.value, true;
  return false;
}

std::vector<ParamGroupSpec> GroupsFromDescription(const dynamic_reconfigure::ConfigDescription& description,
                                                  std::vector<std::string>* skipped) {
  std::vector<ParamGroupSpec> groups;
  for (const auto& g : description.groups) {
    ParamGroupSpec group;
    group.name = g.name;
    for (const auto& d : g.parameters) {
      ParamSpec p;
      p.name = d.name;
      p.description = d.description;
      if (!Kind(d.type, &p.kind)) {
        if (skipped) skipped->push_back(d.name + " (type '" + d.type + "')");
        continue;
      }
      if (p.kind == ParamKind::kString) {
        StringFromConfig(description.dflt, d.name, &p.default_string);
      } else {
        NumberFromConfig(description.min, d.name, &p.min);
        NumberFromConfig(description.max, d.name, &p.max);
        NumberFromConfig(description.dflt, d.name, &p.default_value);
        if (p.kind == ParamKind::kBool) p.min = 0, p.max = 1;
      }
      group.params.push_back(p);
    }
    if (!group.params.empty()) groups.push_back(group);
  }
  return groups;
}

dynamic_reconfigure::Config SingleParameter(const ParamSpec& spec, double value) {
  if (std::isnan(value)) throw std::invalid_argument("ar_overlay panel: " + spec.name + " is NaN");
  dynamic_reconfigure::Config c;
  const double v = spec.max >= spec.min ? std::clamp(value, spec.min, spec.max) : value;
  switch (spec.kind) {
    case ParamKind::kBool: {
      dynamic_reconfigure::BoolParameter b;
      b.name = spec.name;
      b.value = value != 0.0;
      c.bools.push_back(b);
      break;
    }
    case ParamKind::kInt: {
      dynamic_reconfigure::IntParameter i;
      i.name = spec.name;
      i.value = static_cast<int>(std::lround(v));
      c.ints.push_back(i);
      break;
    }
    case ParamKind::kDouble: {
      dynamic_reconfigure::DoubleParameter d;
      d.name = spec.name;
      d.value = v;
      c.doubles.push_back(d);
      break;
    }
    case ParamKind::kString:
      throw std::invalid_argument("ar_overlay panel: " + spec.name + " is a string parameter");
  }
  return c;
}

dynamic_reconfigure::Config SingleParameter(const ParamSpec& spec, const std::string& value) {
  if (spec.kind != ParamKind::kString)
    throw std::invalid_argument("ar_overlay panel: " + spec.name + " is not a string parameter");
  dynamic_reconfigure::Config c;
  dynamic_reconfigure::StrParameter s;
  s.name = spec.name;
  s.value = value;
  c.strs.push_back(s);
  return c;
}

}  // namespace ar_overlay
