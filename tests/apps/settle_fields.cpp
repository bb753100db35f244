// The scene's `settle` block (apps/src/scene_tables.cpp: settle_fields): its defaults, what it
// fills in the World's settings, what OUT/scene.json writes back, and the errors that name the
// field for a bad value or a collider whose motion would not wait.
#include <gtest/gtest.h>

#include <string>

#include "json_reader.hpp"
#include "scene.hpp"

namespace invfem::app {
namespace {

// A small cloth scene with `extra`'s top-level fields.
Scene scene_with(const nlohmann::json& extra, const std::vector<std::string>& overrides = {}) {
  nlohmann::json j = nlohmann::json::parse(R"({"frames": 2, "cloths": [{"name": "cloth",
      "grid": {"width": 1, "height": 1, "nx": 4, "ny": 4}, "transform": {"translate": [0, 1, 0]}}]})");
  if (extra.is_object()) j.update(extra);
  return scene_from_json(j, "settle_test.json", overrides);
}

// The message of the InputError that loading throws, "" when it loads.
std::string error_of(const nlohmann::json& extra, const std::vector<std::string>& overrides = {}) {
  try {
    scene_with(extra, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SettleFields, NoSettleByDefault) {
  const Scene s = scene_with(nlohmann::json::object());
  EXPECT_EQ(s.solver.settle.duration, 0.0);
  EXPECT_TRUE(s.solver.settle.gravity);
}

TEST(SettleFields, FillTheWorldsSettingsAndAreWrittenBack) {
  const Scene s = scene_with({{"settle", {{"duration", 1.5}, {"gravity", false}}}});
  EXPECT_EQ(s.solver.settle.duration, 1.5);
  EXPECT_FALSE(s.solver.settle.gravity);
  const nlohmann::json back = to_json(s);
  EXPECT_EQ(back["settle"]["duration"], 1.5);
  EXPECT_EQ(back["settle"]["gravity"], false);
  EXPECT_EQ(back["settle"]["gravity_ramp"], 0.0);
  EXPECT_EQ(scene_with({{"settle", {{"duration", 1}, {"gravity", false}, {"gravity_ramp", 0.5}}}}).solver.settle.gravity_ramp,
            0.5);
  EXPECT_EQ(scene_with(nlohmann::json::object(), {"settle.duration=2"}).solver.settle.duration, 2.0);
}

TEST(SettleFields, BadValuesNameTheField) {
  for (const auto& [extra, named] : std::vector<std::pair<nlohmann::json, std::string>>{
           {{{"settle", {{"duration", -1}}}}, "$.settle.duration"},
           {{{"settle", {{"duration", "2 s"}}}}, "$.settle.duration"},
           {{{"settle", {{"duration", 1e9}}}}, "$.settle.duration"},
           {{{"settle", {{"gravity", 0}}}}, "$.settle.gravity"},
           {{{"settle", {{"gravity_ramp", -0.5}}}}, "$.settle.gravity_ramp"},
           {{{"settle", {{"duration", 1}, {"gravity_ramp", 0.5}}}}, "$.settle.gravity_ramp"},
           {{{"settle", {{"duratoin", 1}}}}, "duratoin"},
           {{{"settle", 2}}, "settle"}}) {
    const std::string e = error_of(extra);
    EXPECT_NE(e.find(named), std::string::npos) << extra.dump() << ": " << e;
    EXPECT_NE(e.find("settle_test.json"), std::string::npos) << e;
  }
  // --set settle.duration=nan: not a number the scene accepts.
  const std::string e = error_of(nlohmann::json::object(), {"settle.duration=nan"});
  EXPECT_NE(e.find("settle.duration"), std::string::npos) << e;
}

TEST(SettleFields, AnAnalyticColliderWithAMotionCannotWait) {
  const nlohmann::json ball = {{"name", "ball"}, {"type", "sphere"}, {"radius", 0.1},
                               {"motion", {{"velocity", {0, 1, 0}}}}};
  EXPECT_EQ(error_of({{"colliders", {ball}}}), "");  // without a settle it moves from the start
  const std::string e = error_of({{"colliders", {ball}}, {"settle", {{"duration", 1}}}});
  EXPECT_NE(e.find("$.colliders[0].motion"), std::string::npos) << e;
  EXPECT_NE(e.find("settle"), std::string::npos) << e;
  nlohmann::json still = ball;
  still.erase("motion");
  EXPECT_EQ(error_of({{"colliders", {still}}, {"settle", {{"duration", 1}}}}), "");
}

}  // namespace
}  // namespace invfem::app
