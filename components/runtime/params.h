#pragma once
// Parameters: plain structs with defaults in the declaration, bound to YAML by a Serialize method
// (the pattern of Drake's yaml archives):
//
//   struct NoiseParams {
//     double object_position_sigma = 0.005;  // m
//     template <typename Archive>
//     void Serialize(Archive* a) { a->Visit(DMPL_NVP(object_position_sigma)); }
//   };
//
// Reading is strict: an unknown key, a value of the wrong type or shape is a ConfigError that
// names the source (file) and the full key path, with the line number.
//
// A numeric field's bounds are declared beside it, once: `a->Visit(DMPL_NVP(gain), AtLeast(0))`.
// CheckBounds (what each struct's Validate calls, with its cross-field checks) checks every
// bounded field, and every element of a bounded list, naming the key.
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace dmpl {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

template <typename T>
struct NameValue {
  const char* name;
  T* value;
};
#define DMPL_NVP(field) ::dmpl::NameValue<decltype(field)>{#field, &(field)}

// The values a number may take: an interval, each end open or closed (NaN never holds).
struct Bound {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
  bool Holds(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string Text() const;  // "must be > 0", "must be in [0, 2]", ...
};
inline Bound Above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true}; }
inline Bound AtLeast(double lo) { return {lo, std::numeric_limits<double>::infinity()}; }
inline Bound InRange(double lo, double hi) { return {lo, hi}; }
inline Bound AboveUpTo(double lo, double hi) { return {lo, hi, true}; }

namespace internal {
struct ProbeArchive {
  template <typename T>
  void Visit(const NameValue<T>&) {}
  template <typename T>
  void Visit(const NameValue<T>&, const Bound&) {}
};
template <typename T, typename = void>
struct IsSerializable : std::false_type {};
template <typename T>
struct IsSerializable<T, std::void_t<decltype(std::declval<T&>().Serialize(
                             static_cast<ProbeArchive*>(nullptr)))>> : std::true_type {};
template <typename T>
struct IsVector : std::false_type {};
template <typename T>
struct IsVector<std::vector<T>> : std::true_type {};
template <typename T>
struct IsArray : std::false_type {};
template <typename T, size_t N>
struct IsArray<std::array<T, N>> : std::true_type {};
template <typename T>
struct IsOptional : std::false_type {};
template <typename T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <typename T>
struct IsStringMap : std::false_type {};
template <typename T>
struct IsStringMap<std::map<std::string, T>> : std::true_type {};
// A value type that reads itself from any YAML node (a scalar or a list, say):
// `static T FromYaml(const YAML::Node&)` throwing std::invalid_argument with what is wrong, and
// `YAML::Node ToYaml() const`.
template <typename T, typename = void>
struct HasYamlConversion : std::false_type {};
template <typename T>
struct HasYamlConversion<T, std::void_t<decltype(T::FromYaml(std::declval<const YAML::Node&>())),
                                        decltype(std::declval<const T&>().ToYaml())>>
    : std::true_type {};
}  // namespace internal

// Reads a struct from a YAML map.
class YamlReadArchive {
 public:
  // `source` names where the YAML came from (a file, "--set"); `path` is the key path of `node`.
  YamlReadArchive(YAML::Node node, std::string source, std::string path)
      : node_(std::move(node)), source_(std::move(source)), path_(std::move(path)) {}

  template <typename T>
  static void Load(const YAML::Node& node, const std::string& source, const std::string& path,
                   T* out) {
    static_assert(internal::IsSerializable<T>::value, "T needs a Serialize(Archive*) method");
    YamlReadArchive archive(node, source, path);
    archive.ExpectMap(node, path);
    out->Serialize(&archive);
    archive.RejectUnknownKeys();
  }

  template <typename T>
  void Visit(const NameValue<T>& nv) {
    visited_.insert(nv.name);
    const YAML::Node& const_node = node_;
    const YAML::Node child = const_node[nv.name];
    if (!child.IsDefined() || child.IsNull()) return;  // keep the default
    Read(child, Join(path_, nv.name), nv.value);
  }
  template <typename T>
  void Visit(const NameValue<T>& nv, const Bound&) {  // checked by CheckBounds
    Visit(nv);
  }

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& path,
                         const std::string& what) const;

 private:
  static std::string Join(const std::string& a, const std::string& b) {
    return a.empty() ? b : a + "." + b;
  }
  void ExpectMap(const YAML::Node& node, const std::string& path) const;
  void ExpectScalar(const YAML::Node& node, const std::string& path, const char* kind) const;
  void RejectUnknownKeys() const;

  void Read(const YAML::Node& n, const std::string& path, double* v) const;
  void Read(const YAML::Node& n, const std::string& path, int* v) const;
  void Read(const YAML::Node& n, const std::string& path, int64_t* v) const;
  void Read(const YAML::Node& n, const std::string& path, bool* v) const;
  void Read(const YAML::Node& n, const std::string& path, std::string* v) const;

  template <typename T>
  void Read(const YAML::Node& n, const std::string& path, T* v) const {
    if constexpr (internal::HasYamlConversion<T>::value) {
      try {
        *v = T::FromYaml(n);
      } catch (const std::invalid_argument& e) {
        Fail(n, path, e.what());
      }
    } else if constexpr (internal::IsSerializable<T>::value) {
      YamlReadArchive sub(n, source_, path);
      sub.ExpectMap(n, path);
      v->Serialize(&sub);
      sub.RejectUnknownKeys();
    } else if constexpr (internal::IsVector<T>::value) {
      if (!n.IsSequence()) Fail(n, path, "expected a list");
      v->clear();
      v->resize(n.size());
      for (size_t i = 0; i < n.size(); ++i) {
        Read(n[i], path + "[" + std::to_string(i) + "]", &(*v)[i]);
      }
    } else if constexpr (internal::IsArray<T>::value) {
      if (!n.IsSequence() || n.size() != v->size()) {
        Fail(n, path, "expected a list of " + std::to_string(v->size()) + " values");
      }
      for (size_t i = 0; i < n.size(); ++i) {
        Read(n[i], path + "[" + std::to_string(i) + "]", &(*v)[i]);
      }
    } else if constexpr (internal::IsOptional<T>::value) {
      v->emplace();
      Read(n, path, &**v);
    } else if constexpr (internal::IsStringMap<T>::value) {
      ExpectMap(n, path);
      v->clear();
      for (const auto& kv : n) {
        const std::string key = kv.first.as<std::string>();
        Read(kv.second, Join(path, key), &(*v)[key]);
      }
    } else {
      static_assert(!sizeof(T*), "unsupported parameter type");
    }
  }

  YAML::Node node_;
  std::string source_;
  std::string path_;
  std::set<std::string> visited_;
};

// Writes a struct to a YAML map (to print the effective configuration or write calibrated values).
class YamlWriteArchive {
 public:
  template <typename T>
  static YAML::Node Save(const T& value) {
    YamlWriteArchive archive;
    const_cast<T&>(value).Serialize(&archive);
    return archive.node_;
  }

  template <typename T>
  void Visit(const NameValue<T>& nv) {
    node_[nv.name] = ToNode(*nv.value);
  }
  template <typename T>
  void Visit(const NameValue<T>& nv, const Bound&) {
    Visit(nv);
  }

 private:
  template <typename T>
  static YAML::Node ToNode(const T& v) {
    if constexpr (internal::HasYamlConversion<T>::value) {
      return v.ToYaml();
    } else if constexpr (internal::IsSerializable<T>::value) {
      return Save(v);
    } else if constexpr (internal::IsOptional<T>::value) {
      return v ? ToNode(*v) : YAML::Node();
    } else if constexpr (internal::IsVector<T>::value || internal::IsArray<T>::value) {
      YAML::Node seq(YAML::NodeType::Sequence);
      for (const auto& e : v) seq.push_back(ToNode(e));
      seq.SetStyle(YAML::EmitterStyle::Flow);
      return seq;
    } else if constexpr (internal::IsStringMap<T>::value) {
      YAML::Node map(YAML::NodeType::Map);
      for (const auto& [k, e] : v) map[k] = ToNode(e);
      return map;
    } else {
      return YAML::Node(v);
    }
  }
  YAML::Node node_{YAML::NodeType::Map};
};

// Checks the bounds declared in a struct's Serialize (and its nested structs'): the first value
// out of its bounds is a ConfigError naming `source` and the key.
class BoundsCheckArchive {
 public:
  BoundsCheckArchive(std::string source, std::string path)
      : source_(std::move(source)), path_(std::move(path)) {}

  template <typename T>
  void Visit(const NameValue<T>& nv) {
    Nested(path_ + "." + nv.name, *nv.value);
  }
  template <typename T>
  void Visit(const NameValue<T>& nv, const Bound& bound) {
    Check(path_ + "." + nv.name, *nv.value, bound);
  }

 private:
  template <typename T>
  void Nested(const std::string& path, T& v) {
    if constexpr (internal::IsSerializable<T>::value) {
      BoundsCheckArchive sub(source_, path);
      v.Serialize(&sub);
    } else if constexpr (internal::IsVector<T>::value) {
      for (size_t i = 0; i < v.size(); ++i) Nested(path + "[" + std::to_string(i) + "]", v[i]);
    } else if constexpr (internal::IsStringMap<T>::value) {
      for (auto& [key, e] : v) Nested(path + "." + key, e);
    }
  }
  template <typename T>
  void Check(const std::string& path, const T& v, const Bound& bound) const {
    if constexpr (std::is_arithmetic_v<T>) {
      if (!bound.Holds(static_cast<double>(v))) Fail(path, bound, static_cast<double>(v));
    } else if constexpr (internal::IsVector<T>::value || internal::IsArray<T>::value) {
      for (size_t i = 0; i < v.size(); ++i) {
        Check(path + "[" + std::to_string(i) + "]", v[i], bound);
      }
    } else if constexpr (internal::IsStringMap<T>::value) {
      for (const auto& [key, e] : v) Check(path + "." + key, e, bound);
    } else {
      static_assert(!sizeof(T*), "bounds apply to numbers and lists or maps of numbers");
    }
  }
  [[noreturn]] void Fail(const std::string& path, const Bound& bound, double value) const;

  std::string source_;
  std::string path_;
};

template <typename T>
void CheckBounds(const T& params, const std::string& source, const std::string& section) {
  BoundsCheckArchive archive(source, section);
  const_cast<T&>(params).Serialize(&archive);
}

// Loads a YAML file; a missing file or a syntax error is a ConfigError naming the file.
YAML::Node LoadYamlFile(const std::string& path);

// Applies "a.b.c=value" to `root` (value parsed as YAML, so numbers stay numbers). Intermediate
// maps are created; a path through a non-map is a ConfigError.
void ApplySetOverride(YAML::Node root, const std::string& assignment);

// Overlays `overlay` onto `base`: maps are merged key by key, anything else replaces.
void MergeYaml(YAML::Node base, const YAML::Node& overlay);

}  // namespace dmpl
