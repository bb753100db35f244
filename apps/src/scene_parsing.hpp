#pragma once
// Private to the scene parser (scene.cpp, scene_cloth.cpp): the field parsers and JSON writers
// the object kinds share.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <initializer_list>
#include <vector>

#include "json_reader.hpp"
#include "scene.hpp"

namespace invfem::app::scene_detail {

// The rows of `table` with these keys, as a table of their own (in the table's order): a collider
// reads and writes only the fields of its type.
template <class S>
FieldTable<S> rows_of(const FieldTable<S>& table, std::initializer_list<const char*> keys) {
  std::vector<Field<S>> rows;
  for (const auto& d : table.fields())
    for (const char* k : keys)
      if (d.key == k) rows.push_back(d);
  return FieldTable<S>(std::move(rows));
}

// The fields of `spec`'s table that have a member, as a JSON object (the rows without one are the
// caller's to add).
template <class S>
nlohmann::json fields_json(const FieldTable<S>& table, const S& spec) {
  nlohmann::json j = nlohmann::json::object();
  table.write(j, spec);
  return j;
}
template <class S>
nlohmann::json fields_json(const S& spec) {
  return fields_json(S::fields(), spec);
}

// A scene's [x, y, z] as a module's Vec3, and back (exact both ways).
inline Vec3 to_vec3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
inline std::array<double, 3> vec3_json(const Vec3& v) { return {v[0], v[1], v[2]}; }

ScalarTrack parse_track(const Fields& f, const std::string& key, double fallback);
Transform parse_transform(const Fields& f);
// With `motions`, each box may also hold a "motion" (parse_motion), appended there (solids).
std::vector<PinBox> parse_pin_boxes(const Fields& f, std::vector<MotionScript>* motions = nullptr);
PinBox parse_pin_box(const Fields& b, bool with_motion = false);
PlasticParams parse_plasticity(const Fields& f);
MotionScript parse_motion(const Fields& f);
// A mesh path relative to the scene file's folder, made absolute; checked to exist if asked.
std::filesystem::path parse_mesh_path(const Fields& f, const std::string& key, const std::filesystem::path& dir,
                                      bool check_files);

nlohmann::json track_json(const ScalarTrack& t);
nlohmann::json transform_json(const Transform& t);
nlohmann::json pin_boxes_json(const std::vector<PinBox>& boxes, const std::vector<MotionScript>* motions = nullptr);
nlohmann::json motion_json(const MotionScript& m);
nlohmann::json plasticity_json(const PlasticParams& p);

ClothSpec parse_cloth(const Fields& f, const std::filesystem::path& dir, bool check_files);
nlohmann::json cloth_json(const ClothSpec& c);

}  // namespace invfem::app::scene_detail
