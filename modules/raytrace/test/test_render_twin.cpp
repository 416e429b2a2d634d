// `photoscene render` (renderTwinCommand): output names for one and several views.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "photoscene/raytrace/render_twin.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;

// A copy of the bundled sample's ground-truth twin whose scene.json has `views` input views
// (copies of view 0) and absolute paths to the geometry, photos and label images.
fs::path twinWithViews(const fs::path& dir, int views) {
  const fs::path src = fs::path(PS_SOURCE_DIR) / "samples/data/living-room/gt/twin";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy(src, dir, fs::copy_options::recursive);
  nlohmann::json j;
  std::ifstream(src / "scene.json") >> j;
  auto absolute = [&](nlohmann::json& v) {
    v = fs::weakly_canonical(src / v.get<std::string>()).string();
  };
  absolute(j["geometry"]);
  nlohmann::json view = j["views"][0];
  for (const char* key : {"image", "segments"})
    if (view.contains(key)) absolute(view[key]);
  j["views"] = nlohmann::json::array();
  for (int i = 0; i < views; ++i) j["views"].push_back(view);
  std::ofstream(dir / "scene.json") << j.dump(1);
  return dir;
}

TEST(Raytrace_RenderTwin, several_views_are_written_as_stem_view_i) {
  const fs::path tmp =
      fs::temp_directory_path() / ("ps_test_render_twin_" + std::to_string(::getpid()));
  TwinRenderRequest req;
  req.options.spp = 1;
  req.width = 8;
  req.height = 6;
  // two input views: img_view0.png, img_view1.png (no img.png)
  req.twinDir = twinWithViews(tmp / "two", 2);
  req.output = tmp / "img.png";
  std::vector<fs::path> out = renderTwinCommand(req);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0], tmp / "img_view0.png");
  EXPECT_EQ(out[1], tmp / "img_view1.png");
  for (const fs::path& p : out) EXPECT_TRUE(fs::exists(p)) << p;
  EXPECT_FALSE(fs::exists(tmp / "img.png"));
  // one input view: the name as given
  req.twinDir = twinWithViews(tmp / "one", 1);
  req.output = tmp / "single.exr";
  out = renderTwinCommand(req);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], tmp / "single.exr");
  EXPECT_TRUE(fs::exists(tmp / "single.exr"));
  EXPECT_FALSE(fs::exists(tmp / "single_view0.exr"));
  fs::remove_all(tmp);
}

}  // namespace
}  // namespace ps
