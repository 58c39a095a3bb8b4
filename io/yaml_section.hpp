#pragma once
// Internal to io/: reading one YAML mapping of a configuration file key by key. Shared by the
// odometry (config_yaml.cpp) and back-end (backend_config_yaml.cpp) parsers so that both report
// mistakes the same way: "<dotted.key>: <problem>".
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <yaml-cpp/yaml.h>

#include "io/config_yaml.hpp"

namespace dammloam::io {

// One YAML mapping with the dotted path that leads to it. Every key read is remembered so
// that leftovers (typos, keys of another version) are reported instead of silently ignored.
class Section {
 public:
  Section(YAML::Node node, std::string path) : node_(std::move(node)), path_(std::move(path)) {
    if (node_ && !node_.IsNull() && !node_.IsMap()) Fail("", "expected a mapping");
  }

  template <typename T>
  void Get(const std::string& key, T& value) {
    known_.insert(key);
    if (!node_ || node_.IsNull()) return;
    const YAML::Node v = node_[key];
    if (!v) return;
    T read{};
    try {
      if (!v.IsScalar()) throw YAML::Exception(YAML::Mark::null_mark(), "not a scalar");
      read = v.as<T>();
    } catch (const YAML::Exception&) {
      Fail(key, "expected " + TypeName<T>() + ", got '" + Dump(v) + "'");
    }
    // YAML reads .inf and .nan as numbers; no setting means either, and the range checks
    // (x > 0, x >= 0) would let an infinity through.
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(read)) Fail(key, "expected a finite number, got '" + Dump(v) + "'");
    }
    value = read;
  }

  Section Child(const std::string& key) {
    known_.insert(key);
    return Section(node_ && node_.IsMap() ? node_[key] : YAML::Node(), Join(key));
  }

  void RejectUnknownKeys() const {
    if (!node_ || !node_.IsMap()) return;
    for (const auto& kv : node_) {
      // A list or mapping as a key (`? [a, b]: 1`) names no setting; as<std::string>() would
      // throw yaml-cpp's bare "bad conversion" instead of a ConfigError naming the place.
      if (!kv.first.IsScalar() && !kv.first.IsNull()) {
        throw ConfigError((path_.empty() ? std::string("top level") : path_) +
                          ": has a key that is a list or mapping, not a name (line " +
                          std::to_string(kv.first.Mark().line + 1) + ")");
      }
      const std::string key = kv.first.as<std::string>();
      if (!known_.count(key)) Fail(key, "unknown key");
    }
  }

  // A key of an earlier release that a newer one replaced: named with its replacement rather
  // than reported as a typo.
  void Retired(const std::string& key, const std::string& replacement) const {
    if (node_ && node_.IsMap() && node_[key]) Fail(key, "was replaced by " + replacement);
  }

  // Throws ConfigError "<path>.<key>: <what>" (just "<path>: <what>" for an empty key).
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const {
    throw ConfigError((key.empty() ? path_ : Join(key)) + ": " + what);
  }

 private:
  template <typename T>
  static std::string TypeName() {
    if constexpr (std::is_same_v<T, bool>) return "true or false";
    else if constexpr (std::is_integral_v<T>) return "an integer";
    else if constexpr (std::is_floating_point_v<T>) return "a number";
    else return "a string";
  }
  static std::string Dump(const YAML::Node& v) {
    std::ostringstream out;
    out << v;
    return out.str();
  }
  std::string Join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  YAML::Node node_;
  std::string path_;
  std::set<std::string> known_;
};

// Reads a whole file; a missing file or broken YAML is a ConfigError naming the file.
inline YAML::Node LoadYamlFile(const std::filesystem::path& file) {
  try {
    return YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw ConfigError(file.string() + ": cannot open");
  } catch (const YAML::Exception& e) {
    throw ConfigError(file.string() + ": invalid YAML: " + e.what());
  }
}

}  // namespace dammloam::io
