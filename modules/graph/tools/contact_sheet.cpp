// Writes a contact sheet of the whole graph library: every graph at its defaults and at two
// random parameter draws, each rendered as a lit sphere (Lambert + GGX).
//
// usage: ps_graph_contact_sheet OUT.jpg [--library DIR] [--maps N] [--cell N] [--only NAME]
//        [--png COPY.png]   (also writes a lossless copy, e.g. for viewers without JPEG)
//        [--plane 1]        (a flat, frontal plane instead of the sphere: patterns undistorted)
//        [--prefix P]       (only the graphs whose name starts with P)
#include "photoscene/core.hpp"
#include "photoscene/graph.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT.jpg [--library DIR] [--maps N] [--cell N] [--only NAME]\n",
                 argv[0]);
    return 2;
  }
  std::string out = argv[1], folder, only, png, prefix;
  bool plane = false;
  int mapSize = 256, cell = 150;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--library")
      folder = argv[i + 1];
    else if (k == "--maps")
      mapSize = std::stoi(argv[i + 1]);
    else if (k == "--cell")
      cell = std::stoi(argv[i + 1]);
    else if (k == "--only")
      only = argv[i + 1];
    else if (k == "--png")
      png = argv[i + 1];
    else if (k == "--plane")
      plane = std::stoi(argv[i + 1]) != 0;
    else if (k == "--prefix")
      prefix = argv[i + 1];
  }
  try {
    const ps::GraphLibrary lib = ps::GraphLibrary::load(folder);
    std::vector<std::string> names = lib.names();
    if (!only.empty()) names = {only};
    if (!prefix.empty())
      names.erase(std::remove_if(names.begin(), names.end(),
                                 [&](const std::string& s) { return s.rfind(prefix, 0) != 0; }),
                  names.end());
    const int perRow = argc > 0 && std::getenv("PS_SHEET_PER_ROW")
                           ? std::atoi(std::getenv("PS_SHEET_PER_ROW"))
                           : 4;
    const int labelH = 16;
    const int rows = (int(names.size()) + perRow - 1) / perRow;
    cv::Mat sheet(rows * (cell + labelH), perRow * 3 * cell, CV_8UC3, cv::Scalar(20, 20, 20));
    for (size_t gi = 0; gi < names.size(); ++gi) {
      ps::MaterialGraph g = lib.create(names[gi]);
      const int r = int(gi) / perRow, c = int(gi) % perRow;
      for (int v = 0; v < 3; ++v) {
        g.setValues(v == 0 ? g.defaultValues() : g.randomValues(1000 + v, 0.5f));
        ps::MaterialMaps m = g.evaluate(mapSize);
        ps::PreviewOptions po;
        po.size = cell;
        if (plane) po.shape = ps::PreviewShape::Plane, po.uvRepeat = 1.f;
        cv::Mat img = ps::renderMaterialPreview(m, po);
        cv::Mat srgb = ps::linearToSrgb(img, CV_8U), bgr;
        cv::cvtColor(srgb, bgr, cv::COLOR_RGB2BGR);
        bgr.copyTo(sheet(cv::Rect((c * 3 + v) * cell, r * (cell + labelH) + labelH, cell, cell)));
      }
      cv::putText(sheet, names[gi] + " (" + g.category() + ")",
                  cv::Point(c * 3 * cell + 4, r * (cell + labelH) + 12), cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
      std::fprintf(stderr, "%s\n", names[gi].c_str());
    }
    const std::string tmp = out + ".tmp" + std::filesystem::path(out).extension().string();
    if (!cv::imwrite(tmp, sheet, {cv::IMWRITE_JPEG_QUALITY, 85})) {
      std::fprintf(stderr, "cannot write %s\n", tmp.c_str());
      return 1;
    }
    std::filesystem::rename(tmp, out);
    if (!png.empty() && !cv::imwrite(png, sheet)) {
      std::fprintf(stderr, "cannot write %s\n", png.c_str());
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
