#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/report.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;
using io::TempDir;

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// The bundled ground-truth twin, copied with what its scene.json names (../../room_exact.obj,
/// ../../photos, ../../segments).
fs::path copySampleTwin(const TempDir& dir) {
  const fs::path src = fs::path(PS_SOURCE_DIR) / "samples/data/living-room";
  fs::copy(src, dir / "living-room", fs::copy_options::recursive);
  return dir / "living-room/gt/twin";
}

/// A stand-in for the bundled viewer, so these tests do not depend on node_modules.
fs::path fakeViewer(const TempDir& dir) {
  fs::create_directories(dir / "viewer_build");
  io::writeTextFile(dir / "viewer_build/photoscene-viewer.js",
                    "window.PhotosceneViewer = {start: function () {}};\n");
  return dir / "viewer_build";
}

TEST(Report_Write, sample_twin_report_references_every_part_and_view_without_metrics) {
  TempDir dir("ps_report");
  const fs::path out = copySampleTwin(dir);
  ASSERT_FALSE(fs::exists(out / "metrics.json"));
  ReportOptions o;
  o.viewerDir = fakeViewer(dir);
  const ReportSummary s = writeReport(out, o);
  ASSERT_TRUE(fs::exists(out / "report.html"));
  const std::string page = io::readTextFile(out / "report.html");
  EXPECT_EQ(s.views, 1);
  EXPECT_FALSE(s.metricsFound);
  EXPECT_TRUE(contains(page, "No metrics.json"));
  const io::ObjMesh obj =
      io::readObj(fs::path(PS_SOURCE_DIR) / "samples/data/living-room/room_exact.obj");
  EXPECT_EQ(s.parts, static_cast<int>(obj.materialNames.size()));
  for (const auto& part : obj.materialNames) {
    EXPECT_TRUE(contains(page, "id=\"part-" + part + "\"")) << part;
    EXPECT_TRUE(contains(page, "textures/" + part + "_albedo.png")) << part;
  }
  EXPECT_TRUE(contains(page, "id=\"view0\""));
  EXPECT_TRUE(contains(page, "../../photos/view0.png"));  // photo relative to OUT
  EXPECT_TRUE(contains(page, "Go to input view 0"));
  EXPECT_TRUE(contains(page, "no renders/view0.png"));  // no renders in the GT twin
  // the viewer: twin.gltf exported on the way, embedded into a classic script
  EXPECT_TRUE(s.viewerWritten) << s.viewerNote;
  EXPECT_TRUE(fs::exists(out / "twin.gltf"));
  EXPECT_TRUE(fs::exists(out / "viewer/photoscene-viewer.js"));
  const std::string data = io::readTextFile(out / "viewer/twin_data.js");
  EXPECT_TRUE(contains(data, "window.__psTwinGltf = {"));
  EXPECT_TRUE(contains(data, "data:application/octet-stream;base64,"));
  EXPECT_TRUE(contains(data, "data:image/png;base64,"));
  EXPECT_FALSE(contains(data, "\"textures/"));  // every image embedded
  EXPECT_TRUE(contains(page, "<script src=\"viewer/twin_data.js\"></script>"));
  EXPECT_FALSE(contains(page, "type=\"module\""));  // classic scripts only: works from file://
}

TEST(Report_Write, a_part_whose_category_the_scene_gives_says_how_its_graph_was_chosen) {
  TempDir dir("ps_report");
  const fs::path out = copySampleTwin(dir);
  const fs::path mf = out / "materials/sofa_fabric.json";
  nlohmann::json m = io::readJsonFile(mf);
  m["graph"] = "fabric_twill";
  m["fit"]["category_given"] = "fabric";  // what export writes for parts.<name>.category
  m["fit"]["candidates"] = nlohmann::json::array(
      {{{"graph", "fabric_twill"}, {"category", "fabric"}, {"score", 0.6}, {"votes", 3}},
       {{"graph", "fabric_basket"}, {"category", "fabric"}, {"score", 0.4}, {"votes", 2}}});
  m["fit"]["finalists"] = nlohmann::json::array(
      {{{"graph", "homogeneous"}, {"loss", 0.1}, {"contrast", 0.01}, {"qualifies", true}},
       {{"graph", "fabric_twill"}, {"loss", 0.12}, {"contrast", 0.05}, {"qualifies", true}}});
  io::writeJsonFile(mf, m);
  ReportOptions o;
  o.viewerDir = fakeViewer(dir);
  writeReport(out, o);
  const std::string page = io::readTextFile(out / "report.html");
  const std::string row = page.substr(page.find("id=\"candidates-sofa_fabric\""));
  const std::string cells = row.substr(0, row.find("</tr>"));
  EXPECT_TRUE(contains(cells, "The scene gives the category <b>fabric</b>: only its graphs"));
  EXPECT_FALSE(contains(cells, "A graph must beat the homogeneous loss"));
  EXPECT_TRUE(contains(page, "{ \"category\": \"wood\" } }"));  // how to give one
}

TEST(Report_Write, each_part_shows_its_top_candidates_with_scores_previews_and_how_to_force) {
  TempDir dir("ps_report");
  const fs::path out = copySampleTwin(dir);
  // what the select stage writes: fit.candidates, best first (here six: the page shows five)
  const fs::path mf = out / "materials/sofa_fabric.json";
  nlohmann::json m = io::readJsonFile(mf);
  const std::vector<std::string> graphs = {"tile_hexagon", "plaster_stucco", "paint_glossy",
                                           "fabric_twill", "fabric_basket",  "not_a_graph"};
  m["graph"] = "plaster_stucco";
  m["fit"]["candidates"] = nlohmann::json::array();
  for (size_t i = 0; i < graphs.size(); ++i)
    m["fit"]["candidates"].push_back(
        {{"graph", graphs[i]}, {"category", "c"}, {"score", 0.5 - 0.05 * i}, {"votes", 2}});
  // and the synthesis's finalists with their verdicts (what select and fit write)
  m["fit"]["finalists"] = nlohmann::json::array(
      {{{"graph", "tile_hexagon"},
        {"loss", 0.12},
        {"contrast", 0.31},
        {"contrast_coarse", 0.4},
        {"chroma_spread", 0.9},
        {"qualifies", false}},
       {{"graph", "plaster_stucco"}, {"loss", 0.15}, {"contrast", 0.05}, {"qualifies", true}},
       {{"graph", "homogeneous"}, {"loss", 0.19}, {"contrast", 0.01}, {"qualifies", true}},
       {{"graph", "wallpaper_stripes"},
        {"loss", 0.2},
        {"contrast", 0.05},
        {"chroma_spread", 0.3},
        {"chroma_outside", 0.32},
        {"qualifies", false}}});
  m["fit"]["photo_contrast"] = 0.06;
  m["fit"]["photo_contrast_coarse"] = 0.045;
  m["fit"]["photo_chroma_spread"] = 0.2;
  io::writeJsonFile(mf, m);
  ReportOptions o;
  o.viewerDir = fakeViewer(dir);
  writeReport(out, o);
  const std::string page = io::readTextFile(out / "report.html");
  ASSERT_TRUE(contains(page, "id=\"candidates-sofa_fabric\""));
  const std::string row = page.substr(page.find("id=\"candidates-sofa_fabric\""));
  const std::string cells = row.substr(0, row.find("</tr>"));
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_TRUE(contains(cells, graphs[i])) << graphs[i];
    // a preview of each graph at its default parameters, written once, linked from the page
    EXPECT_TRUE(fs::exists(out / "previews" / (graphs[i] + ".png"))) << graphs[i];
    EXPECT_TRUE(contains(cells, "previews/" + graphs[i] + ".png")) << graphs[i];
  }
  EXPECT_FALSE(contains(cells, "not_a_graph"));  // top 5 only
  EXPECT_TRUE(contains(cells, "score 0.5,"));
  EXPECT_TRUE(contains(cells, "<b>plaster_stucco</b>"));  // the chosen one is marked
  EXPECT_TRUE(contains(cells, "\"sofa_fabric\": { \"graph\": \"tile_hexagon\" }"));
  // why the lowest loss did not win: it failed the contrast test (and the colour test)
  EXPECT_TRUE(contains(cells,
                       "tile_hexagon loss 0.12, contrast 0.31 (0.4 at 2 x 2 cells), colour "
                       "spread 0.9 (more structure, colours or pixel error than the photo "
                       "allows)"));
  EXPECT_TRUE(contains(cells, "Its colour spread: 0.2."));
  // and one in colours the photo lacks (the gamut test)
  EXPECT_TRUE(contains(cells,
                       "wallpaper_stripes loss 0.2, contrast 0.05, colour spread 0.3, 32 % in "
                       "colours the photo lacks (more structure, colours or pixel error"));
  // a finalist without the coarse value (a materials file written before it) shows the rest
  EXPECT_TRUE(contains(cells, "<b>plaster_stucco</b> loss 0.15, contrast 0.05;"));
  EXPECT_TRUE(contains(cells, "typical local contrast: 0.06 (0.045 at 2 x 2 cells)."));
  EXPECT_TRUE(contains(cells, "the contrast it adds to the homogeneous render's"));
  // the cells are as large as the materials file says (fit.coarse_contrast_scale; 2 when absent)
  m["fit"]["coarse_contrast_scale"] = 3;
  io::writeJsonFile(mf, m);
  writeReport(out, o);
  const std::string page3 = io::readTextFile(out / "report.html");
  EXPECT_TRUE(contains(page3, "typical local contrast: 0.06 (0.045 at 3 x 3 cells)."));
  EXPECT_TRUE(contains(page3, "contrast 0.31 (0.4 at 3 x 3 cells)"));
  EXPECT_FALSE(contains(page3, "2 x 2 cells"));
  const cv::Mat preview = io::readImage(out / "previews/tile_hexagon.png");
  EXPECT_EQ(preview.cols, o.candidatePreviewSize);
  // parts without candidates (the other GT materials) get no row
  EXPECT_FALSE(contains(page, "id=\"candidates-floor\""));
}

TEST(Report_Write, renders_metrics_and_loss_curves_are_shown) {
  TempDir dir("ps_report");
  const fs::path out = copySampleTwin(dir);
  fs::create_directories(out / "renders");
  // a render 10% brighter than the photo
  cv::Mat photo = io::readImage(out / "../../photos/view0.png");
  io::writeImage(out / "renders/view0.png", photo * 1.1);
  io::writeJsonFile(
      out / "metrics.json",
      {{"views", {{{"view", 0}, {"srgb255", {{"rmse", 3.5}, {"psnr", 31.25}, {"ssim", 0.93}}}}}},
       {"parts", {{"floor", {{"view", 0}, {"pixels", 1234}, {"srgb255", {{"rmse", 4.75}}}}}}},
       {"stages", {{"geometry", 1.5}, {"align", 0.25}}},
       {"total_seconds", 12.5},
       {"preset", "fast"}});
  nlohmann::json floor = io::readJsonFile(out / "materials/floor.json");
  floor["fit"] = {{"view", 0},
                  {"loss", 0.0125},
                  {"seconds", 2.5},
                  {"skipped", nullptr},
                  {"history", {1.0, 0.5, 0.2, 0.0125}}};
  io::writeJsonFile(out / "materials/floor.json", floor);
  ReportOptions o;
  o.viewer = false;
  const ReportSummary s = writeReport(out, o);
  EXPECT_TRUE(s.metricsFound);
  EXPECT_EQ(s.rendersFound, 1);
  EXPECT_EQ(s.diffsWritten, 1);
  ASSERT_TRUE(fs::exists(out / "renders/view0_diff.png"));
  const cv::Mat diff = io::readImage(out / "renders/view0_diff.png");
  EXPECT_EQ(diff.size(), photo.size());
  EXPECT_GT(cv::mean(diff)[0], 0.01);
  const std::string page = io::readTextFile(out / "report.html");
  EXPECT_TRUE(contains(page, "renders/view0.png"));
  EXPECT_TRUE(contains(page, "renders/view0_diff.png"));
  EXPECT_TRUE(contains(page, "class=\"wipe\""));
  EXPECT_TRUE(contains(page, "31.25"));  // view PSNR
  EXPECT_TRUE(contains(page, "4.75"));   // floor RMSE
  EXPECT_TRUE(contains(page, "<polyline"));
  EXPECT_TRUE(contains(page, "geometry"));  // stage times
  EXPECT_TRUE(contains(page, "preset fast"));
  // a second run keeps the diff (written once) and still succeeds
  EXPECT_EQ(writeReport(out, o).diffsWritten, 0);
}

TEST(Report_Write, partial_or_broken_metrics_do_not_fail_it) {
  TempDir dir("ps_report");
  const fs::path out = copySampleTwin(dir);
  io::writeTextFile(out / "metrics.json",
                    R"({"views": [{"view": 0, "srgb255": {"psnr": "n/a"}}], "stages": 3})");
  ReportOptions o;
  o.viewer = false;
  EXPECT_NO_THROW(writeReport(out, o));
  io::writeTextFile(out / "metrics.json", "{ not json");
  EXPECT_NO_THROW(writeReport(out, o));
  EXPECT_TRUE(contains(io::readTextFile(out / "report.html"), "metrics.json is not readable"));
}

TEST(Report_Write, a_folder_without_scene_json_is_bad_input) {
  TempDir dir("ps_report");
  EXPECT_THROW(writeReport(dir.path()), InputError);
}

/// One HTTP/1.1 request to 127.0.0.1:port; returns the whole response.
std::string httpRequest(int port, const std::string& request) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    ::close(fd);
    return "";
  }
  ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string out;
  char buf[4096];
  ssize_t n;
  while ((n = ::recv(fd, buf, sizeof(buf), 0)) > 0) out.append(buf, static_cast<size_t>(n));
  ::close(fd);
  return out;
}

TEST(Report_Server, serves_the_folder_with_content_types_and_refuses_traversal) {
  TempDir dir("ps_serve");
  fs::create_directories(dir / "site/viewer");
  io::writeTextFile(dir / "site/report.html", "<html>hello</html>");
  io::writeTextFile(dir / "site/viewer/a.js", "var a = 1;");
  io::writeTextFile(dir / "site/twin.gltf", "{}");
  io::writeTextFile(dir / "secret.txt", "secret");
  StaticFileServer server(dir / "site", 0);
  ASSERT_GT(server.port(), 0);
  EXPECT_EQ(server.url("report.html"),
            "http://127.0.0.1:" + std::to_string(server.port()) + "/report.html");
  std::atomic<bool> stop{false};
  std::thread t([&] { server.serve(&stop); });
  const int port = server.port();
  auto get = [&](const std::string& method, const std::string& target) {
    return httpRequest(port, method + " " + target + " HTTP/1.1\r\nHost: x\r\n\r\n");
  };
  std::string r = get("GET", "/report.html");
  EXPECT_TRUE(contains(r, "HTTP/1.1 200 OK")) << r;
  EXPECT_TRUE(contains(r, "Content-Type: text/html")) << r;
  EXPECT_TRUE(contains(r, "<html>hello</html>"));
  EXPECT_TRUE(contains(get("GET", "/"), "<html>hello</html>"));  // the folder: its report.html
  EXPECT_TRUE(contains(get("GET", "/viewer/a.js?v=1"), "Content-Type: text/javascript"));
  EXPECT_TRUE(contains(get("GET", "/twin.gltf"), "Content-Type: model/gltf+json"));
  r = get("HEAD", "/report.html");
  EXPECT_TRUE(contains(r, "Content-Length: 18")) << r;
  EXPECT_FALSE(contains(r, "hello"));
  EXPECT_TRUE(contains(get("GET", "/missing.png"), "404"));
  for (const char* evil :
       {"/../secret.txt", "/viewer/../../secret.txt", "/%2e%2e/secret.txt", "/..%2fsecret.txt"}) {
    r = get("GET", evil);
    EXPECT_TRUE(contains(r, "403")) << evil << "\n" << r;
    EXPECT_FALSE(contains(r, "secret\n") || contains(r, "\r\n\r\nsecret")) << evil;
  }
  EXPECT_TRUE(contains(get("POST", "/report.html"), "405"));
  EXPECT_TRUE(contains(httpRequest(port, "garbage\r\n\r\n"), "400"));
  EXPECT_THROW(StaticFileServer(dir / "site", port), InputError);     // the port is taken
  EXPECT_THROW(StaticFileServer(dir / "secret.txt", 0), InputError);  // not a folder
  stop = true;
  t.join();
}

TEST(Report_Server, content_types) {
  EXPECT_EQ(contentTypeFor("a/report.html"), "text/html; charset=utf-8");
  EXPECT_EQ(contentTypeFor("x.JS"), "text/javascript; charset=utf-8");
  EXPECT_EQ(contentTypeFor("twin.bin"), "application/octet-stream");
  EXPECT_EQ(contentTypeFor("t.png"), "image/png");
  EXPECT_EQ(contentTypeFor("m.json"), "application/json");
}

}  // namespace
}  // namespace ps
