#include <gtest/gtest.h>

#include <cmath>

#include "rig_sim/scene.h"
#include "test_util.h"

namespace rig_sim {

TEST(Scene, DefaultIsTheThesisTriangleWithConeOneOnX) {
  const Scene s = DefaultScene();
  ASSERT_EQ(s.cones.size(), 3u);
  EXPECT_LT(s.ConeCentroid().norm(), 1e-12);
  EXPECT_GT(s.cones[0].base_m.x(), 0.0);
  EXPECT_NEAR(s.cones[0].base_m.y(), 0.0, 1e-12);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR((s.cones[i].base_m - s.cones[(i + 1) % 3].base_m).norm(), 1.5, 1e-12);
    EXPECT_NEAR(s.cones[i].radius_m(), 0.71 / 7.0, 1e-12);
    EXPECT_FALSE(s.cones[i].collars.empty());
  }
}

TEST(Scene, EveryShippedLayoutLoads) {
  for (const char* name : {"default.yaml", "thesis_indoor.yaml", "clutter.yaml", "stacked.yaml"}) {
    Scene s;
    std::string err;
    EXPECT_TRUE(LoadSceneYaml(LayoutsDir() + "/" + name, &s, &err)) << name << ": " << err;
    EXPECT_GE(s.cones.size(), 3u) << name;
  }
  Scene from_file, built = DefaultScene();
  std::string err;
  ASSERT_TRUE(LoadSceneYaml(LayoutsDir() + "/default.yaml", &from_file, &err));
  for (int i = 0; i < 3; ++i) EXPECT_LT((from_file.cones[i].base_m - built.cones[i].base_m).norm(), 1e-12);
}

TEST(Scene, StackedAndPlainConesAndDistractorsParse) {
  Scene s;
  std::string err;
  ASSERT_TRUE(ParseSceneYaml(R"(
cones:
  - {x_m: 0.5, y_m: 0, height_m: 0.10, style: plain}
  - {x_m: 0.5, y_m: 0, z_m: 0.02, height_m: 0.10, style: plain}
  - {x_m: -0.5, y_m: 0.3, height_m: 0.10, style: plain}
boxes: [{x_m: 2, y_m: 1, sx_m: 0.5, sy_m: 0.5, sz_m: 0.2}]
patches: [{x_m: -1, y_m: 1}]
people: [{x_m: 3, y_m: 3}]
ground: grass
)",
                             &s, &err))
      << err;
  ASSERT_EQ(s.cones.size(), 3u);
  EXPECT_NEAR(s.cones[1].base_m.z(), 0.02, 1e-12);
  EXPECT_TRUE(s.cones[0].collars.empty());
  EXPECT_NEAR(s.boxes[0].center_m.z(), 0.1, 1e-12);  // boxes sit on the ground
  EXPECT_EQ(s.people.size(), 1u);
  EXPECT_EQ(s.ground, GroundStyle::kGrass);
}

TEST(Scene, BadLayoutsAreRefusedWithAMessageNamingTheEntry) {
  Scene s = DefaultScene();
  std::string err;
  EXPECT_FALSE(ParseSceneYaml("cones:\n  - {x_m: 1}\n  - {x_m: 2}\n  - {x_m: 0, height_m: 0.05}\n", &s, &err));
  EXPECT_NE(err.find("cones[2]"), std::string::npos) << err;
  EXPECT_NE(err.find("height_m"), std::string::npos) << err;
  EXPECT_FALSE(ParseSceneYaml("cones:\n  - {x_m: 0, style: tall}\n", &s, &err));
  EXPECT_NE(err.find("style"), std::string::npos) << err;
  EXPECT_FALSE(ParseSceneYaml("ground: asphalt\n", &s, &err));
  EXPECT_NE(err.find("no cones"), std::string::npos) << err;
  EXPECT_FALSE(ParseSceneYaml("cones: [{x_m: .nan}]\n", &s, &err));
  EXPECT_FALSE(ParseSceneYaml("equilateral: {side_m: 1.5, hieght_m: 0.71}\n", &s, &err));  // no silent default
  EXPECT_NE(err.find("unknown key 'equilateral.hieght_m' (did you mean 'height_m'?)"), std::string::npos) << err;
  EXPECT_FALSE(LoadSceneYaml("/nonexistent/layout.yaml", &s, &err));
  EXPECT_NE(err.find("cannot open"), std::string::npos);
  EXPECT_EQ(s.cones.size(), 3u);  // untouched on failure
}

}  // namespace rig_sim
