// The inventory's schema: strict keys, no positions, the frame's anchors of heights of their own.
#include "cone_survey/inventory.h"

#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "rig_model/strict_yaml.h"

namespace cone_survey {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    ParseInventory(text, "inv.yaml");
  } catch (const rig_model::FileError& e) {
    return e.what();
  }
  return "";
}

const char* kThree =
    "cones:\n  - {height_m: 0.91, style: road}\n  - {height_m: 0.30, style: plain}\n"
    "  - {height_m: 0.71}\n";

TEST(Inventory, ReadsConesAndAnchors) {
  const Inventory inv = ParseInventory(std::string(kThree) + "origin: 2\nx_axis: 0\n", "inv.yaml");
  ASSERT_EQ(inv.cones.size(), 3u);
  EXPECT_EQ(inv.origin, 2);
  EXPECT_EQ(inv.x_axis, 0);
  EXPECT_EQ(inv.cones[1].style, rig_model::ConeStyle::kPlain);
  EXPECT_EQ(inv.cones[2].style, rig_model::ConeStyle::kRoad);
  EXPECT_EQ(inv.Name(1), "cones[1] (0.3 m plain)");
  // Written back and read again.
  const Inventory again = ParseInventory(InventoryYaml(inv.cones, inv.origin, inv.x_axis), "again.yaml");
  EXPECT_EQ(again.origin, 2);
  EXPECT_EQ(again.cones[0].height_m, 0.91);
}

TEST(Inventory, BadInventoriesAreRefusedAndNamed) {
  EXPECT_NE(ErrorOf(std::string(kThree) + "orign: 1\n").find("unknown key 'orign' (did you mean 'origin'?)"),
            std::string::npos);
  EXPECT_NE(ErrorOf("cones:\n  - {height_m: 0.91, x_m: 1}\n  - {height_m: 0.3}\n  - {height_m: 0.46}\n")
                .find("inv.yaml:2: cones[0].x_m: an inventory gives no positions"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kThree) + "origin: 3\n").find("origin: must be the index of one of the 3 cones"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kThree) + "origin: 1\nx_axis: 1\n").find("x_axis: must differ from origin"),
            std::string::npos);
  const std::string shared =
      ErrorOf("cones:\n  - {height_m: 0.71}\n  - {height_m: 0.30}\n  - {height_m: 0.71}\norigin: 0\nx_axis: 1\n");
  EXPECT_NE(shared.find("origin: cones[0] (0.71 m road) shares its height with cones[2] (0.71 m road)"),
            std::string::npos)
      << shared;
  EXPECT_NE(ErrorOf("cones:\n  - {height_m: 0.91}\n  - {height_m: 0.3}\n").find("the inventory has 2 cones"),
            std::string::npos);
  EXPECT_NE(ErrorOf("cones:\n  - {height_m: 1.5}\n  - {height_m: 0.3}\n  - {height_m: 0.46}\n")
                .find("cones[0].height_m: 1.5 is outside"),
            std::string::npos);
  EXPECT_NE(ErrorOf("cones:\n  - {style: road}\n  - {height_m: 0.3}\n  - {height_m: 0.46}\n").find("cones[0]"),
            std::string::npos);
  EXPECT_NE(ErrorOf("").find("empty inventory"), std::string::npos);
}

}  // namespace
}  // namespace cone_survey
