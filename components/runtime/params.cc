#include "components/runtime/params.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace dmpl {
namespace {

std::string LineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return "";
  return " (line " + std::to_string(mark.line + 1) + ")";
}

std::string Describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "nothing";
  }
}

}  // namespace

void YamlReadArchive::Fail(const YAML::Node& node, const std::string& path,
                           const std::string& what) const {
  throw ConfigError("config error in " + source_ + ": key '" + path + "'" + LineOf(node) + ": " +
                    what + ", got " + Describe(node));
}

void YamlReadArchive::ExpectMap(const YAML::Node& node, const std::string& path) const {
  if (!node.IsMap()) {
    throw ConfigError("config error in " + source_ + ": " +
                      (path.empty() ? std::string("top level") : "key '" + path + "'") +
                      LineOf(node) + ": expected a map of keys, got " + Describe(node));
  }
}

void YamlReadArchive::ExpectScalar(const YAML::Node& node, const std::string& path,
                                   const char* kind) const {
  if (!node.IsScalar()) Fail(node, path, std::string("expected ") + kind);
}

void YamlReadArchive::RejectUnknownKeys() const {
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (visited_.count(key)) continue;
    std::string known;
    for (const auto& k : visited_) known += (known.empty() ? "" : ", ") + k;
    throw ConfigError("config error in " + source_ + ": unknown key '" + Join(path_, key) + "'" +
                      LineOf(kv.first) + "; known keys here: " + known);
  }
}

void YamlReadArchive::Read(const YAML::Node& n, const std::string& path, double* v) const {
  ExpectScalar(n, path, "a number");
  double value = 0.0;
  if (!YAML::convert<double>::decode(n, value)) Fail(n, path, "expected a number");
  if (!std::isfinite(value)) Fail(n, path, "expected a finite number");
  *v = value;
}

void YamlReadArchive::Read(const YAML::Node& n, const std::string& path, int* v) const {
  ExpectScalar(n, path, "an integer");
  int value = 0;
  if (!YAML::convert<int>::decode(n, value)) Fail(n, path, "expected an integer");
  *v = value;
}

void YamlReadArchive::Read(const YAML::Node& n, const std::string& path, int64_t* v) const {
  ExpectScalar(n, path, "an integer");
  int64_t value = 0;
  if (!YAML::convert<int64_t>::decode(n, value)) Fail(n, path, "expected an integer");
  *v = value;
}

void YamlReadArchive::Read(const YAML::Node& n, const std::string& path, bool* v) const {
  ExpectScalar(n, path, "true or false");
  bool value = false;
  if (!YAML::convert<bool>::decode(n, value)) Fail(n, path, "expected true or false");
  *v = value;
}

void YamlReadArchive::Read(const YAML::Node& n, const std::string& path, std::string* v) const {
  ExpectScalar(n, path, "a string");
  *v = n.Scalar();
}

namespace {

// Whether `text` is UTF-8 without NUL: what a YAML file is (a binary given by mistake is not).
bool IsUtf8Text(const std::string& text) {
  size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    // The bytes that follow a lead byte: 0 (ASCII), 1 (110xxxxx), 2 (1110xxxx), 3 (11110xxx).
    const int follow = c < 0x80          ? 0
                       : (c >> 5) == 0x6  ? 1
                       : (c >> 4) == 0xe  ? 2
                       : (c >> 3) == 0x1e ? 3
                                          : -1;
    if (c == 0 || follow < 0 || text.size() - i <= static_cast<size_t>(follow)) return false;
    for (int k = 1; k <= follow; ++k) {
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
    }
    i += follow + 1;
  }
  return true;
}

}  // namespace

namespace {

std::string Number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

std::string Bound::Text() const {
  const bool has_lo = lo > -std::numeric_limits<double>::infinity();
  const bool has_hi = hi < std::numeric_limits<double>::infinity();
  if (has_lo && has_hi) {
    return "must be in " + std::string(lo_open ? "(" : "[") + Number(lo) + ", " + Number(hi) +
           (hi_open ? ")" : "]");
  }
  if (has_lo) return std::string("must be ") + (lo_open ? "> " : ">= ") + Number(lo);
  if (has_hi) return std::string("must be ") + (hi_open ? "< " : "<= ") + Number(hi);
  return "must be a number";
}

void BoundsCheckArchive::Fail(const std::string& path, const Bound& bound, double value) const {
  throw ConfigError("config error in " + source_ + ": key '" + path + "': " + bound.Text() +
                    ", got " + Number(value));
}

YAML::Node LoadYamlFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError("config error: cannot open file '" + path + "'");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  const std::string text = bytes.str();
  if (!IsUtf8Text(text)) {
    throw ConfigError("config error in " + path +
                      ": not a YAML text file (it holds bytes that are not UTF-8 text)");
  }
  try {
    YAML::Node node = YAML::Load(text);
    if (node.IsNull()) return YAML::Node(YAML::NodeType::Map);
    return node;
  } catch (const YAML::ParserException& e) {
    throw ConfigError("config error in " + path + ": YAML syntax error at line " +
                      std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

void ApplySetOverride(YAML::Node root, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ConfigError("config error in --set: expected key=value, got '" + assignment + "'");
  }
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  YAML::Node value;
  try {
    value = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError("config error in --set " + key + ": cannot parse value '" + text + "'");
  }
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) throw ConfigError("config error in --set: empty part in key '" + key + "'");
    parts.push_back(part);
  }
  YAML::Node node = root;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = node[parts[i]];
    if (!child.IsDefined() || child.IsNull()) {
      child = YAML::Node(YAML::NodeType::Map);
      node[parts[i]] = child;
      child = node[parts[i]];
    } else if (!child.IsMap()) {
      throw ConfigError("config error in --set " + key + ": '" + parts[i] + "' is not a map");
    }
    node.reset(child);
  }
  node[parts.back()] = value;
}

void MergeYaml(YAML::Node base, const YAML::Node& overlay) {
  if (!overlay.IsMap()) return;
  for (const auto& kv : overlay) {
    const std::string key = kv.first.as<std::string>();
    YAML::Node existing = base[key];
    if (kv.second.IsMap() && existing.IsDefined() && existing.IsMap()) {
      MergeYaml(existing, kv.second);
    } else {
      base[key] = YAML::Clone(kv.second);
    }
  }
}

}  // namespace dmpl
