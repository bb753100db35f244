#include "sheet_command.hpp"

#include <iostream>
#include <stdexcept>

#include "cli_args.hpp"
#include "invfem/renders/image.hpp"
#include "invfem/renders/image_compare.hpp"
#include "json_reader.hpp"

namespace invfem::app {

const char* const kSheetHelp =
    "usage: invfem sheet IMAGE.png... --out SHEET.png [--columns N] [--label TEXT]...\n"
    "\n"
    "Tiles the PNGs row by row, left to right, into one contact sheet (cells of the largest\n"
    "image's size). --columns defaults to the number of images (one row). --label, repeated once\n"
    "per image in the same order, writes a caption under each cell (none when absent).\n";

int sheet_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "sheet", {"--out", "--columns", "--label"}, {"--help", "-h"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kSheetHelp;
    return 0;
  }
  if (args.positional.empty()) throw InputError("sheet: expected one or more PNG files (see invfem sheet --help)");
  if (!args.has("--out")) throw InputError("sheet: --out SHEET.png is required");
  const int count = static_cast<int>(args.positional.size());
  const int columns = args.integer("--columns", count, 1, 1000);
  const std::vector<std::string> labels = args.has("--label") ? args.all("--label") : std::vector<std::string>{};
  if (!labels.empty() && labels.size() != args.positional.size())
    throw InputError("sheet: " + std::to_string(labels.size()) + " --label options for " + std::to_string(count) +
                     " images (give one per image, or none)");
  std::vector<renders::Image> images;
  for (const std::string& file : args.positional) {
    try {
      images.push_back(renders::read_png(file));
    } catch (const std::runtime_error& e) {  // names the file
      throw InputError(e.what());
    }
  }
  renders::write_png(args.value("--out"), renders::contact_sheet(images, columns, labels));
  return 0;
}

}  // namespace invfem::app
