#pragma once
// Private to the scene parser (scene.cpp, scene_cloth.cpp): the field parsers and JSON writers
// the object kinds share.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <vector>

#include "json_fields.hpp"
#include "scene.hpp"

namespace invfem::app::scene_detail {

ScalarTrack parse_track(const Fields& f, const std::string& key, double fallback);
Transform parse_transform(const Fields& f);
// With `motions`, each box may also hold a "motion" (parse_motion), appended there (solids).
std::vector<PinBox> parse_pin_boxes(const Fields& f, std::vector<MotionSpec>* motions = nullptr);
PinBox parse_pin_box(const Fields& b, bool with_motion = false);
PlasticitySpec parse_plasticity(const Fields& f);
// The fields choosing a constitutive model: model, compression_limit, hardening_deformation,
// hardening_strength (solids' and cloths' materials alike).
void parse_model_choice(const Fields& f, std::string& model, double& compression_limit, double& hardening_deformation,
                        double& hardening_strength);
MotionSpec parse_motion(const Fields& f);
// A mesh path relative to the scene file's folder, made absolute; checked to exist if asked.
std::filesystem::path parse_mesh_path(const Fields& f, const std::string& key, const std::filesystem::path& dir,
                                      bool check_files);

nlohmann::json track_json(const ScalarTrack& t);
nlohmann::json transform_json(const Transform& t);
nlohmann::json pin_boxes_json(const std::vector<PinBox>& boxes, const std::vector<MotionSpec>* motions = nullptr);
nlohmann::json motion_json(const MotionSpec& m);
nlohmann::json plasticity_json(const PlasticitySpec& p);

ClothSpec parse_cloth(const Fields& f, const std::filesystem::path& dir, bool check_files);
nlohmann::json cloth_json(const ClothSpec& c);

}  // namespace invfem::app::scene_detail
