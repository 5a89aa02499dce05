// One parameter table per component: the names of a Config struct's fields, in the units the
// field names carry, read the same way from ROS parameters, dynamic_reconfigure and YAML files.
// ROS-free; rig_model/ros/param_table_ros.h adds the ROS and dynamic_reconfigure sides.
//
// A component declares its table once:
//
//   const ParamTable<NodeConfig>& Params() {
//     static const ParamTable<NodeConfig> table = ParamTable<NodeConfig>()
//         .Add("max_tilt_deg", [](NodeConfig& c) -> double& { return c.segmenter.max_tilt_deg; })
//         .AddEnum("peak_refinement", [](NodeConfig& c) -> int& { return c.refinement; },
//                  {"outline", "templates", "none"});
//     return table;
//   }
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "rig_model/strict_yaml.h"

namespace rig_model {

// A parameter's value as ROS, dynamic_reconfigure and YAML carry it.
using ParamValue = std::variant<bool, int, double, std::string>;

template <class Config>
class ParamTable {
 public:
  template <class T>
  using Field = T& (*)(Config&);  // a captureless lambda returning the struct's field

  ParamTable&& Add(std::string name, Field<double> f) && { return Push(std::move(name), f); }
  ParamTable&& Add(std::string name, Field<int> f) && { return Push(std::move(name), f); }
  ParamTable&& Add(std::string name, Field<bool> f) && { return Push(std::move(name), f); }
  ParamTable&& Add(std::string name, Field<std::string> f) && { return Push(std::move(name), f); }
  // An enum stored as an int; written as one of `names` (or its index, as dynamic_reconfigure writes it).
  ParamTable&& AddEnum(std::string name, Field<int> f, std::vector<std::string> names) && {
    entries_.push_back({std::move(name), f, std::move(names)});
    return std::move(*this);
  }

  std::vector<std::string> Names() const {
    std::vector<std::string> names;
    for (const Entry& e : entries_) names.push_back(e.name);
    return names;
  }
  bool Has(const std::string& name) const { return Find(name) != nullptr; }

  ParamValue Get(const Config& config, const std::string& name) const {
    const Entry& e = Require(name);
    Config& c = const_cast<Config&>(config);  // the field accessors are shared by Get and Set
    return std::visit([&](auto field) -> ParamValue { return field(c); }, e.field);
  }

  // Sets `name` from `value`, converting int -> double, a whole double -> int, and an enum's name
  // or index -> int. Throws std::invalid_argument("<name> must be ...") on a wrong type.
  void Set(Config* config, const std::string& name, const ParamValue& value) const {
    const Entry& e = Require(name);
    try {
      std::visit([&](auto field) { Assign(e, &field(*config), value); }, e.field);
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument(name + " " + error.what());
    }
  }

  // Reads every key of the mapping `map` (at `where` in reader's file) into `config`; unknown or
  // misspelt keys, and values of the wrong type, throw FileError naming the file, line and key.
  void FromYaml(const YAML::Node& map, const StrictReader& reader, const std::string& where, Config* config) const {
    reader.CheckKeys(map, Names(), where);
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      const Entry& e = Require(key);
      try {
        std::visit([&](auto field) { Assign(e, &field(*config), FromScalar(kv.second, e)); }, e.field);
      } catch (const std::invalid_argument& error) {
        reader.Fail(kv.second, FieldPath(where, key), error.what());
      }
    }
  }

 private:
  using AnyField = std::variant<Field<double>, Field<int>, Field<bool>, Field<std::string>>;
  struct Entry {
    std::string name;
    AnyField field;
    std::vector<std::string> enum_names;  // empty unless an enum
  };

  template <class T>
  ParamTable&& Push(std::string name, Field<T> f) {
    entries_.push_back({std::move(name), f, {}});
    return std::move(*this);
  }
  const Entry* Find(const std::string& name) const {
    auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.name == name; });
    return it == entries_.end() ? nullptr : &*it;
  }
  const Entry& Require(const std::string& name) const {
    if (const Entry* e = Find(name)) return *e;
    const std::string nearest = NearestKey(name, Names());
    throw std::invalid_argument(name + " is unknown" + (nearest.empty() ? "" : " (did you mean " + nearest + "?)"));
  }

  [[noreturn]] static void Wrong(const Entry&, const std::string& must_be) {
    throw std::invalid_argument("must be " + must_be);
  }
  static std::string EnumList(const Entry& e) {
    std::string list;
    for (const std::string& n : e.enum_names) list += (list.empty() ? "" : ", ") + n;
    return list;
  }

  static void Assign(const Entry& e, double* out, const ParamValue& v) {
    if (const double* d = std::get_if<double>(&v)) {
      *out = *d;
    } else if (const int* i = std::get_if<int>(&v)) {
      *out = *i;
    } else if (const std::string* s = std::get_if<std::string>(&v); s && (s->empty() || *s == "nan")) {
      *out = std::numeric_limits<double>::quiet_NaN();  // a launch file's "" or "nan": not set
    } else {
      Wrong(e, "a number");
    }
  }
  static void Assign(const Entry& e, int* out, const ParamValue& v) {
    if (!e.enum_names.empty()) return AssignEnum(e, out, v);
    if (const int* i = std::get_if<int>(&v)) {
      *out = *i;
    } else if (const double* d = std::get_if<double>(&v);
               d && *d >= std::numeric_limits<int>::min() && *d <= std::numeric_limits<int>::max() &&
               *d == std::trunc(*d)) {  // range first: casting an out-of-range double is undefined
      *out = static_cast<int>(*d);
    } else {
      Wrong(e, "an integer");
    }
  }
  static void AssignEnum(const Entry& e, int* out, const ParamValue& v) {
    const int n = static_cast<int>(e.enum_names.size());
    if (const std::string* s = std::get_if<std::string>(&v)) {
      const auto it = std::find(e.enum_names.begin(), e.enum_names.end(), *s);
      if (it == e.enum_names.end()) Wrong(e, "one of " + EnumList(e) + " (got '" + *s + "')");
      *out = static_cast<int>(it - e.enum_names.begin());
    } else if (const int* i = std::get_if<int>(&v); i && *i >= 0 && *i < n) {
      *out = *i;
    } else {
      Wrong(e, "one of " + EnumList(e));
    }
  }
  static void Assign(const Entry& e, bool* out, const ParamValue& v) {
    if (!std::holds_alternative<bool>(v)) Wrong(e, "true or false");
    *out = std::get<bool>(v);
  }
  static void Assign(const Entry& e, std::string* out, const ParamValue& v) {
    if (!std::holds_alternative<std::string>(v)) Wrong(e, "a string");
    *out = std::get<std::string>(v);
  }

  // YAML scalars carry no type: read them as the field's type wants them.
  static ParamValue FromScalar(const YAML::Node& n, const Entry& e) {
    if (!n.IsScalar()) Wrong(e, "a single value");
    const std::string& s = n.Scalar();
    if (std::holds_alternative<Field<std::string>>(e.field)) return s;
    if (!e.enum_names.empty() && !s.empty() && !std::isdigit(static_cast<unsigned char>(s[0]))) return s;
    if (std::holds_alternative<Field<bool>>(e.field)) {
      bool b = false;
      if (!YAML::convert<bool>::decode(n, b)) Wrong(e, "true or false");
      return b;
    }
    if (s == "nan" || s == ".nan" || s == ".NaN") return std::numeric_limits<double>::quiet_NaN();
    int i = 0;
    if (YAML::convert<int>::decode(n, i)) return i;
    double d = 0.0;
    if (YAML::convert<double>::decode(n, d)) return d;
    Wrong(e, std::holds_alternative<Field<int>>(e.field) ? "an integer" : "a number");
  }

  std::vector<Entry> entries_;
};

}  // namespace rig_model
