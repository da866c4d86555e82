#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "components/runtime/config.h"
#include "components/runtime/params.h"

namespace dmpl {
namespace {

struct Gains {
  double kp = 1.0;
  std::array<double, 3> axis = {1.0, 0.0, 0.0};
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(kp));
    a->Visit(DMPL_NVP(axis));
  }
};

struct Params {
  double sigma = 0.005;
  int iterations = 50;
  bool enabled = true;
  std::string name = "default";
  std::vector<std::string> fingers = {"T", "F"};
  Gains gains;
  std::map<std::string, Gains> per_finger;
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(sigma));
    a->Visit(DMPL_NVP(iterations));
    a->Visit(DMPL_NVP(enabled));
    a->Visit(DMPL_NVP(name));
    a->Visit(DMPL_NVP(fingers));
    a->Visit(DMPL_NVP(gains));
    a->Visit(DMPL_NVP(per_finger));
  }
};

Params Read(const std::string& yaml) {
  Params p;
  YamlReadArchive::Load(YAML::Load(yaml), "test.yaml", "noise", &p);
  return p;
}

std::string ErrorOf(const std::string& yaml) {
  try {
    Read(yaml);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamsTest, MissingKeysKeepDefaults) {
  const Params p = Read("{}");
  EXPECT_EQ(p.sigma, 0.005);
  EXPECT_EQ(p.iterations, 50);
  EXPECT_TRUE(p.enabled);
  EXPECT_EQ(p.name, "default");
  EXPECT_EQ(p.fingers.size(), 2u);
  EXPECT_EQ(p.gains.kp, 1.0);
}

TEST(ParamsTest, ReadsEveryKind) {
  const Params p = Read(
      "sigma: 0.01\niterations: 7\nenabled: false\nname: x\nfingers: [R]\n"
      "gains: {kp: 3.5, axis: [0, 1, 0]}\nper_finger: {T: {kp: 2}}\n");
  EXPECT_EQ(p.sigma, 0.01);
  EXPECT_EQ(p.iterations, 7);
  EXPECT_FALSE(p.enabled);
  EXPECT_EQ(p.name, "x");
  ASSERT_EQ(p.fingers.size(), 1u);
  EXPECT_EQ(p.fingers[0], "R");
  EXPECT_EQ(p.gains.kp, 3.5);
  EXPECT_EQ(p.gains.axis[1], 1.0);
  EXPECT_EQ(p.per_finger.at("T").kp, 2.0);
}

TEST(ParamsTest, UnknownKeyNamesFileKeyAndLine) {
  const std::string e = ErrorOf("sigma: 0.01\nsigmaa: 0.02\n");
  EXPECT_NE(e.find("test.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key 'noise.sigmaa'"), std::string::npos) << e;
  EXPECT_NE(e.find("line 2"), std::string::npos) << e;
}

TEST(ParamsTest, UnknownNestedKey) {
  const std::string e = ErrorOf("gains: {kp: 1, ki: 2}\n");
  EXPECT_NE(e.find("unknown key 'noise.gains.ki'"), std::string::npos) << e;
}

TEST(ParamsTest, WrongTypesEachHaveTheirMessage) {
  EXPECT_NE(ErrorOf("sigma: abc").find("'noise.sigma'"), std::string::npos);
  EXPECT_NE(ErrorOf("sigma: abc").find("expected a number, got 'abc'"), std::string::npos);
  EXPECT_NE(ErrorOf("iterations: 1.5").find("expected an integer"), std::string::npos);
  EXPECT_NE(ErrorOf("enabled: maybe").find("expected true or false"), std::string::npos);
  EXPECT_NE(ErrorOf("fingers: T").find("expected a list"), std::string::npos);
  EXPECT_NE(ErrorOf("gains: 3").find("expected a map of keys"), std::string::npos);
  EXPECT_NE(ErrorOf("gains: {axis: [1, 2]}").find("expected a list of 3 values"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sigma: [1]").find("expected a number, got a list"), std::string::npos);
  EXPECT_NE(ErrorOf("sigma: .nan").find("finite"), std::string::npos);
}

TEST(ParamsTest, SetOverrideKeepsTypesAndCreatesMaps) {
  YAML::Node root = YAML::Load("noise: {sigma: 0.005}");
  ApplySetOverride(root, "noise.sigma=0.02");
  ApplySetOverride(root, "noise.gains.kp=4");
  ApplySetOverride(root, "noise.fingers=[T, F, M]");
  Params p;
  YamlReadArchive::Load(root["noise"], "x", "noise", &p);
  EXPECT_EQ(p.sigma, 0.02);
  EXPECT_EQ(p.gains.kp, 4.0);
  EXPECT_EQ(p.fingers.size(), 3u);
}

TEST(ParamsTest, SetOverrideErrors) {
  YAML::Node root = YAML::Load("noise: {sigma: 0.005}");
  EXPECT_THROW(ApplySetOverride(root, "noise.sigma"), ConfigError);
  EXPECT_THROW(ApplySetOverride(root, "=3"), ConfigError);
  EXPECT_THROW(ApplySetOverride(root, "noise..sigma=3"), ConfigError);
  EXPECT_THROW(ApplySetOverride(root, "noise.sigma.x=3"), ConfigError);
}

TEST(ParamsTest, MergeOverlaysMapsKeyByKey) {
  YAML::Node base = YAML::Load("a: {x: 1, y: 2}\nb: 3");
  MergeYaml(base, YAML::Load("a: {y: 5, z: 6}"));
  EXPECT_EQ(base["a"]["x"].as<int>(), 1);
  EXPECT_EQ(base["a"]["y"].as<int>(), 5);
  EXPECT_EQ(base["a"]["z"].as<int>(), 6);
  EXPECT_EQ(base["b"].as<int>(), 3);
}

TEST(ParamsTest, WriteThenReadRoundTrips) {
  Params p;
  p.sigma = 0.25;
  p.fingers = {"M"};
  p.per_finger["R"].kp = 9.0;
  Params q;
  YamlReadArchive::Load(YamlWriteArchive::Save(p), "x", "", &q);
  EXPECT_EQ(q.sigma, 0.25);
  EXPECT_EQ(q.fingers, p.fingers);
  EXPECT_EQ(q.per_finger.at("R").kp, 9.0);
}

TEST(ConfigTest, ResolveRejectsUnknownSectionAndMissingFile) {
  const std::string path = ::testing::TempDir() + "/dmpl_config_test.yaml";
  {
    std::ofstream out(path);
    out << "noize: {sigma: 1}\n";
  }
  try {
    Config::Resolve(path, {}, {});
    FAIL() << "expected an error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown section 'noize'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  try {
    Config::Resolve("/nonexistent/x.yaml", {}, {});
    FAIL() << "expected an error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open file '/nonexistent/x.yaml'"),
              std::string::npos);
  }
  {
    std::ofstream out(path);
    out << "run: {seed: [1\n";
  }
  try {
    Config::Resolve(path, {}, {});
    FAIL() << "expected an error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("YAML syntax error"), std::string::npos);
  }
  std::remove(path.c_str());
}

TEST(ConfigTest, ParamsOverlayAndSetApplyInOrder) {
  const std::string base = ::testing::TempDir() + "/dmpl_base.yaml";
  const std::string overlay = ::testing::TempDir() + "/dmpl_overlay.yaml";
  std::ofstream(base) << "run: {seed: 3, tick_timeout_s: 1.5}\n";
  std::ofstream(overlay) << "run: {seed: 4}\n";
  const Config c = Config::Resolve(base, {overlay}, {"run.lockstep=false"});
  RunParams run;
  c.Load("run", &run);
  EXPECT_EQ(run.seed, 4);
  EXPECT_EQ(run.tick_timeout_s, 1.5);
  EXPECT_FALSE(run.lockstep);
  EXPECT_EQ(ResolveLcmUrl("memq://", run), "memq://");
}

TEST(ConfigTest, WithoutASectionLeavesTheOriginalWhole) {
  const std::string path = ::testing::TempDir() + "/dmpl_without.yaml";
  std::ofstream(path) << "run: {seed: 3}\nobject: {mass: 0.2}\n";
  const Config full = Config::Resolve(path, {}, {});
  const Config blind = full.Without("object");
  EXPECT_FALSE(blind.root()["object"].IsDefined());
  EXPECT_EQ(blind.root()["run"]["seed"].as<int>(), 3);
  EXPECT_EQ(full.root()["object"]["mass"].as<double>(), 0.2);  // the clone is a clone
  std::remove(path.c_str());
}

struct Bounded {
  struct Inner {
    double gain = 1.0;
    template <typename Archive>
    void Serialize(Archive* a) {
      a->Visit(DMPL_NVP(gain), InRange(0, 2));
    }
  };
  double step = 0.1;
  int ticks = 1;
  std::vector<double> sigmas = {0.0, 0.5};
  Inner inner;
  std::map<std::string, Inner> per_finger = {{"T", {}}};
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(step), AboveUpTo(0, 1));
    a->Visit(DMPL_NVP(ticks), AtLeast(1));
    a->Visit(DMPL_NVP(sigmas), AtLeast(0));
    a->Visit(DMPL_NVP(inner));
    a->Visit(DMPL_NVP(per_finger));
  }
};

std::string BoundsError(const Bounded& b) {
  try {
    CheckBounds(b, "exp.yaml", "sec");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamsTest, BoundsDeclaredBesideTheFieldsAreCheckedAndNameTheKey) {
  Bounded b;
  EXPECT_EQ(BoundsError(b), "");  // the defaults hold
  b.step = 1.0;                   // the closed end
  EXPECT_EQ(BoundsError(b), "");
  b.step = 0.0;                   // the open end
  EXPECT_EQ(BoundsError(b), "config error in exp.yaml: key 'sec.step': must be in (0, 1], got 0");
  b.step = std::nan("");
  EXPECT_NE(BoundsError(b).find("key 'sec.step'"), std::string::npos);
  b = Bounded{};
  b.ticks = 0;
  EXPECT_NE(BoundsError(b).find("key 'sec.ticks': must be >= 1, got 0"), std::string::npos);
  b = Bounded{};
  b.sigmas[1] = -0.5;  // each element of a list
  EXPECT_NE(BoundsError(b).find("key 'sec.sigmas[1]': must be >= 0, got -0.5"), std::string::npos);
  b = Bounded{};
  b.inner.gain = 3;  // nested structs, and maps of them
  EXPECT_NE(BoundsError(b).find("key 'sec.inner.gain': must be in [0, 2], got 3"),
            std::string::npos);
  b = Bounded{};
  b.per_finger["T"].gain = 1e300;
  EXPECT_NE(BoundsError(b).find("key 'sec.per_finger.T.gain': must be in [0, 2], got 1e+300"),
            std::string::npos);
}

TEST(ParamsTest, BoundedFieldsReadAndWriteLikeAnyOther) {
  Bounded b;
  YamlReadArchive::Load(YAML::Load("{step: 0.5, sigmas: [1, 2], inner: {gain: 1.5}}"), "x", "sec",
                        &b);
  EXPECT_EQ(b.step, 0.5);
  EXPECT_EQ(b.sigmas, (std::vector<double>{1, 2}));
  EXPECT_EQ(b.inner.gain, 1.5);
  EXPECT_EQ(YamlWriteArchive::Save(b)["inner"]["gain"].as<double>(), 1.5);
}

}  // namespace
}  // namespace dmpl
