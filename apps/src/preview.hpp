#pragma once
// Preview PNGs of a run's output: reads OUT/frames/<object>/NNNN.obj and writes OUT/png/NNNN.png.
// `invfem render` and `invfem run --render` share this one path, so a preview made while
// simulating and one made afterwards are the same picture.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "invfem/renders/image.hpp"
#include "scene.hpp"

namespace invfem::app {

struct PreviewOptions {
  int width = 0, height = 0;             // 0: the scene's render size
  std::optional<renders::Camera> camera;  // unset: the scene's camera (or automatic framing)
  bool caption = true;
};

class PreviewRenderer {
 public:
  // `scene` is the scene as run (OUT/scene.json). Creates the OSMesa context.
  PreviewRenderer(std::filesystem::path out_dir, const Scene& scene, PreviewOptions options);
  ~PreviewRenderer();

  // Renders the frame whose files are numbered `number` (frames/<object>/NNNN.obj: the frame plus
  // the scene's first_frame_number); returns the image and writes png/NNNN.png, numbered alike.
  renders::Image render(int number);
  std::filesystem::path png_path(int number) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The frames a run wrote for the scene's objects and drawn bodies, by file number: the highest any
// of them has (-1: none), and the numbers from the scene's first_frame_number to it where one of
// them is missing, each with the first missing file.
struct WrittenFrames {
  int last = -1;
  std::map<int, std::filesystem::path> missing;
};
WrittenFrames written_frames(const std::filesystem::path& out_dir, const Scene& scene);

}  // namespace invfem::app
