#include "rig_model/strict_yaml.h"

#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>
#include "test_util.h"

namespace rig_model {
namespace {

TEST(NearestKey, FindsTyposOnly) {
  const std::vector<std::string> known = {"x_m", "y_m", "z_m", "height_m", "style", "tau"};
  EXPECT_EQ(NearestKey("hieght_m", known), "height_m");
  EXPECT_EQ(NearestKey("heigth_m", known), "height_m");
  EXPECT_EQ(NearestKey("stlye", known), "style");
  EXPECT_EQ(NearestKey("colour_of_the_sky", known), "");
}

TEST(StrictReader, UnknownKeyNamesFileLineFieldAndNearest) {
  const YAML::Node root = YAML::Load("cones:\n  - {x_m: 1.0, y_m: 0.0}\n  - x_m: 0.0\n    hieght_m: 0.71\n");
  const StrictReader reader("cones.yaml");
  reader.CheckKeys(root, {"cones", "equilateral"}, "");
  reader.CheckKeys(root["cones"][0], {"x_m", "y_m", "height_m"}, "cones[0]");
  EXPECT_EQ(ErrorOf([&] {
              reader.CheckKeys(root["cones"][1], {"x_m", "y_m", "height_m"}, "cones[1]");
            }),
            "cones.yaml:4: unknown key 'cones[1].hieght_m' (did you mean 'height_m'?)");
}

TEST(StrictReader, DuplicateKeysAreRefused) {
  const YAML::Node root = YAML::Load("cones:\n  - {x_m: 1.0, height_m: 0.5, height_m: 0.9}\n");
  EXPECT_EQ(ErrorOf([&] {
              StrictReader("d.yaml").CheckKeys(root["cones"][0], {"x_m", "height_m"}, "cones[0]");
            }),
            "d.yaml:2: duplicate key 'cones[0].height_m' (first at line 2)");
}

TEST(StrictReader, UnknownKeyWithoutNearListsTheKnownOnes) {
  const YAML::Node root = YAML::Load("wibble: 3\n");
  EXPECT_EQ(ErrorOf([&] {
              StrictReader("a.yaml").CheckKeys(root, {"cones", "equilateral"}, "");
            }),
            "a.yaml:1: unknown key 'wibble'; known keys: cones, equilateral");
}

TEST(StrictReader, NumbersAreCheckedAndNamed) {
  const YAML::Node root = YAML::Load("a: 1.5\nb: one\nc: .nan\n");
  const StrictReader reader("n.yaml");
  EXPECT_DOUBLE_EQ(reader.Number(root, "", "a", 0.0), 1.5);
  EXPECT_DOUBLE_EQ(reader.Number(root, "", "missing", 7.0), 7.0);
  EXPECT_EQ(ErrorOf([&] { reader.Number(root, "", "b", 0.0); }), "n.yaml:2: b: must be a number");
  EXPECT_EQ(ErrorOf([&] { reader.Number(root, "", "c", 0.0); }), "n.yaml:3: c: must be finite");
  EXPECT_EQ(ErrorOf([&] { reader.RequiredNumber(root, "", "d"); }), "n.yaml:1: d: is missing");
  EXPECT_THROW(reader.CheckKeys(root["a"], {"x"}, "a"), FileError);  // a scalar is not a mapping
}

TEST(LoadYamlFile, NamesTheFileOnEveryFailure) {
  EXPECT_EQ(ErrorOf([] { LoadYamlFile("/nonexistent/rig.yaml"); }), "/nonexistent/rig.yaml: cannot open the file");
  const std::string binary = WriteTestFile("binary.yaml", std::string("a: 1\n\xfe\xff\x00\x01", 9));
  EXPECT_EQ(ErrorOf([&] { LoadYamlFile(binary); }), binary + ": not a text file (invalid UTF-8); expected YAML");
  const std::string broken = WriteTestFile("broken.yaml", "a: [1, 2\nb: 3\n");
  EXPECT_NE(ErrorOf([&] { LoadYamlFile(broken); }).find(broken + ":"), std::string::npos);
  const std::string good = WriteTestFile("good.yaml", "name: caf\xc3\xa9\n");
  EXPECT_EQ(LoadYamlFile(good)["name"].Scalar(), "caf\xc3\xa9");
}

}  // namespace
}  // namespace rig_model
