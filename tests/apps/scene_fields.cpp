// The scene document (apps/scenes/README.md) against the parser: every field table between
// `<!-- fields: SECTION -->` and `<!-- /fields -->` must be the one the specs' field tables
// generate (scene_field_tables: keys, units, defaults, ranges, choices and meanings defined once,
// in apps/src/scene_tables.cpp), and every generated table must appear. With
// INVFEM_UPDATE_GOLDEN=1 the document's tables are rewritten instead.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <variant>

#include "json_reader.hpp"
#include "scene.hpp"

namespace invfem::app {
namespace {

const std::string kDocument = std::string(INVFEM_SOURCE_DIR) + "/apps/scenes/README.md";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// [begin, end) of the text between a section's markers, npos when it has none.
std::pair<std::size_t, std::size_t> table_span(const std::string& doc, const std::string& section) {
  const std::string open = "<!-- fields: " + section + " -->\n";
  const std::size_t a = doc.find(open);
  if (a == std::string::npos) return {std::string::npos, std::string::npos};
  const std::size_t b = doc.find("<!-- /fields -->", a);
  return {a + open.size(), b};
}

TEST(SceneFields, TheDocumentsTablesAreTheParsersFields) {
  std::string doc = read_text(kDocument);
  ASSERT_FALSE(doc.empty()) << kDocument;
  const bool update = std::getenv("INVFEM_UPDATE_GOLDEN") != nullptr;
  for (const auto& [section, table] : scene_field_tables()) {
    const auto [a, b] = table_span(doc, section);
    ASSERT_NE(a, std::string::npos) << kDocument << " has no table for " << section;
    ASSERT_NE(b, std::string::npos) << kDocument << ": the table for " << section << " is not closed";
    if (update) {
      doc.replace(a, b - a, table);
      continue;
    }
    EXPECT_EQ(doc.substr(a, b - a), table)
        << kDocument << ": the `" << section << "` table differs from the parser's fields (apps/src/scene_tables.cpp); "
        << "regenerate it with INVFEM_UPDATE_GOLDEN=1";
  }
  if (update) std::ofstream(kDocument) << doc;
}

TEST(SceneFields, EveryMarkedTableIsGenerated) {
  const std::string doc = read_text(kDocument);
  std::set<std::string> generated;
  for (const auto& t : scene_field_tables()) generated.insert(t.first);
  for (std::size_t at = doc.find("<!-- fields: "); at != std::string::npos; at = doc.find("<!-- fields: ", at + 1)) {
    const std::size_t end = doc.find(" -->", at);
    const std::string section = doc.substr(at + 13, end - at - 13);
    EXPECT_TRUE(generated.count(section)) << kDocument << " marks a table `" << section << "` that no spec generates";
  }
}

// A field a table reads is checked by it: a value outside its range is refused, naming the field.
TEST(SceneFields, ARangeOfTheTableIsWhatTheParserAccepts) {
  for (const auto& d : solver_fields().fields()) {
    if (!std::holds_alternative<Slot<Scene, double>>(d.member)) continue;
    nlohmann::json j = {{"solids", nlohmann::json::array()}, {"cloths", nlohmann::json::array()}};
    j["solver"][d.key] = d.range.hi * 2 + 1;
    try {
      parse_scene(j, "probe.json", false);
      ADD_FAILURE() << "solver." << d.key << " = " << d.range.hi * 2 + 1 << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(d.key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace invfem::app
