// Running the `photoscene` command from a test: what tests/test_cli.cpp and
// tests/test_batch_cli.cpp share. PHOTOSCENE_BIN and PS_BINARY_DIR come from tests/CMakeLists.txt.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "photoscene/io.hpp"
#include "run_command.hpp"

namespace ps::cli_test {

/// Every run shares the exemplar-bank cache of the build tree (built once, by whichever test is
/// first); a cache the caller set already wins.
inline const int kCacheEnv = setenv("PS_CACHE_DIR", PS_BINARY_DIR "/photoscene-cache", 0);

/// `photoscene ARGS` through the shell, stdout and stderr together.
inline Result runPhotoscene(const std::string& args) {
  return runCommand(std::string(PHOTOSCENE_BIN) + " " + args);
}

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// A small valid case in `dir`: a 4 x 2.5 x 3 m room (parts floor, walls, ceiling) in room.obj,
/// one 32 x 24 photo of colour (shade, 0.3, 0.2) whose pixels are all labelled `walls`; returns
/// its scene.json (the ceiling skipped), which the caller writes.
inline nlohmann::json writeTinyCase(const std::filesystem::path& dir, double shade) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "room.obj") << "v -2 0 -1.5\nv 2 0 -1.5\nv 2 0 1.5\nv -2 0 1.5\n"
                                     "v -2 2.5 -1.5\nv 2 2.5 -1.5\nv 2 2.5 1.5\nv -2 2.5 1.5\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "usemtl floor\nf 4/1 3/2 2/3 1/4\n"
                                     "usemtl walls\nf 1/1 2/2 6/3 5/4\nf 2/1 3/2 7/3 6/4\n"
                                     "usemtl ceiling\nf 5/1 6/2 7/3 8/4\n";
  io::writeImage(dir / "photo.png", cv::Mat(24, 32, CV_32FC3, cv::Scalar(shade, 0.3, 0.2)));
  io::writeRawImage(dir / "labels.png", cv::Mat(24, 32, CV_16UC1, cv::Scalar(7)));
  return {{"version", 1},
          {"geometry", "room.obj"},
          {"views",
           {{{"image", "photo.png"},
             {"camera", io::cameraToJson(io::CameraDesc{
                            32, 24, 25, 25, 15.5, 11.5,
                            io::lookAtWorldToCamera(Vec3d(0, 1.4, 1.2), Vec3d(0, 1.0, -1.5))})},
             {"segments", "labels.png"},
             {"segment_parts", {{"7", "walls"}}}}}},
          {"parts", {{"ceiling", {{"skip", true}}}}}};
}

}  // namespace ps::cli_test
