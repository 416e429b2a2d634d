// ps_bench_methods_table --case NAME [--plot FILE.png] METHOD=OUT_DIR[=WALL_SECONDS]...
// The table and plot of bench/bench_methods.sh: one markdown table row per method (preset or
// baseline) from OUT_DIR/metrics.json (written by `photoscene run` and refreshed by
// `photoscene eval`), and a PNG of error against total seconds.
//
// Columns: seconds per stage (the union of the stages over the methods), total seconds (the
// metrics' total_seconds, else the wall seconds given, less the "metrics" stage: scoring the twin
// is not part of the method), input-view RMSE / SSIM / GMSD (sRGB
// 8-bit scale, mean over views), novel-view and relit RMSE (sRGB 8-bit scale, mean over the
// case's ground truth; "-" when the case has none). A method whose OUT_DIR has no metrics.json
// (the run failed) gets a row of "failed".
// Plot: x = total seconds (log scale), y = novel-view RMSE where the case has novel ground truth,
// else input-view RMSE (sRGB 8-bit scale); one point per method; a row named gt-twin (the
// case's true twin, evaluated only) is drawn as a dashed line: the floor set by render noise.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Method {
  std::string name;
  fs::path dir;
  double wall = kNaN;
  bool ok = false;
  std::map<std::string, double> stages;
  double total = kNaN;
  double viewRmse = kNaN, viewSsim = kNaN, viewGmsd = kNaN, novelRmse = kNaN, relitRmse = kNaN;
};

double value(const nlohmann::json& j) {
  return j.is_number() ? j.get<double>() : kNaN;
}

/// Mean of `entry[space][key]` over an array of entries (NaN when none is a number).
double meanOf(const nlohmann::json& arr, const char* key) {
  double s = 0;
  int n = 0;
  if (!arr.is_array()) return kNaN;
  for (const auto& e : arr) {
    if (!e.contains("srgb255")) continue;
    const double v = value(e["srgb255"].value(key, nlohmann::json()));
    if (std::isfinite(v)) s += v, ++n;
  }
  return n ? s / n : kNaN;
}

std::string fmtNum(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void load(Method& m) {
  const fs::path file = m.dir / "metrics.json";
  if (!fs::exists(file)) return;
  try {
    std::ifstream in(file);
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.contains("stages") && j["stages"].is_object())
      for (const auto& [k, v] : j["stages"].items()) m.stages[k] = value(v);
    m.total = value(j.value("total_seconds", nlohmann::json()));
    if (!std::isfinite(m.total)) m.total = m.wall;
    // Scoring the twin (the pipeline's "metrics" stage: renders of every view and ground truth)
    // is not part of the method's run time.
    const auto scoring = m.stages.find("metrics");
    if (scoring != m.stages.end() && std::isfinite(scoring->second) && std::isfinite(m.total))
      m.total -= scoring->second;
    m.viewRmse = meanOf(j.value("views", nlohmann::json()), "rmse");
    m.viewSsim = meanOf(j.value("views", nlohmann::json()), "ssim");
    m.viewGmsd = meanOf(j.value("views", nlohmann::json()), "gmsd");
    m.novelRmse = meanOf(j.value("novel", nlohmann::json()), "rmse");
    m.relitRmse = meanOf(j.value("relit", nlohmann::json()), "rmse");
    m.ok = true;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), e.what());
  }
}

void plot(const std::vector<Method>& methods, const std::string& caseName, const fs::path& file) {
  const bool novel = std::any_of(methods.begin(), methods.end(),
                                 [](const Method& m) { return std::isfinite(m.novelRmse); });
  struct Point {
    double x, y;  // log10 seconds, error
    std::string label;
  };
  std::vector<Point> pts;
  double floorError = kNaN;  // the true twin's error: a horizontal line
  for (const Method& m : methods) {
    const double y = novel ? m.novelRmse : m.viewRmse;
    if (!m.ok || !std::isfinite(y)) continue;
    if (m.name == "gt-twin")
      floorError = y;
    else if (m.total > 0)
      pts.push_back({std::log10(m.total), y, m.name});
  }
  const int W = 760, H = 480, L = 70, R = 200, T = 50, B = 60;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = 0, x1 = 1, y1 = std::isfinite(floorError) ? floorError : 1;
  if (!pts.empty()) {
    double lo = pts[0].x, hi = pts[0].x;
    for (const auto& p : pts)
      lo = std::min(lo, p.x), hi = std::max(hi, p.x), y1 = std::max(y1, p.y);
    x0 = std::floor(lo - 0.1);
    x1 = std::ceil(hi + 0.1);
  }
  y1 *= 1.15;
  auto px = [&](double x, double y) {
    return cv::Point(L + static_cast<int>((x - x0) / (x1 - x0) * (W - L - R)),
                     H - B - static_cast<int>(y / y1 * (H - T - B)));
  };
  const cv::Scalar black(0, 0, 0), gray(200, 200, 200);
  for (double d = x0; d <= x1 + 1e-9; d += 1) {
    for (int k = 2; k < 10 && d < x1; ++k) {
      const double xl = d + std::log10(k);
      cv::line(img, px(xl, 0), px(xl, y1), cv::Scalar(235, 235, 235), 1);
    }
    cv::line(img, px(d, 0), px(d, y1), gray, 1);
    cv::putText(img, fmtNum(std::pow(10.0, d), d < 0 ? 1 : 0), px(d, 0) + cv::Point(-12, 20),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, black, 1, cv::LINE_AA);
  }
  for (int k = 0; k <= 5; ++k) {
    const double y = y1 * k / 5;
    cv::line(img, px(x0, y), px(x1, y), gray, 1);
    cv::putText(img, fmtNum(y, 1), px(x0, y) + cv::Point(-45, 5), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                black, 1, cv::LINE_AA);
  }
  cv::rectangle(img, px(x0, 0), px(x1, y1), black, 1);
  cv::putText(img, "total seconds (log)", cv::Point(L + (W - L - R) / 2 - 70, H - 15),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  cv::putText(img,
              caseName + ": " + (novel ? "novel-view" : "input-view") +
                  " RMSE (sRGB 0-255) against run time",
              cv::Point(L, 30), cv::FONT_HERSHEY_SIMPLEX, 0.55, black, 1, cv::LINE_AA);
  const cv::Scalar colors[] = {{200, 80, 30},  {40, 140, 40},  {30, 30, 200},
                               {160, 40, 160}, {20, 140, 200}, {90, 90, 90}};
  int legendY = T + 10;
  const int legendX = W - R + 15;
  for (size_t i = 0; i < pts.size(); ++i) {
    const cv::Scalar c = colors[i % 6];
    cv::circle(img, px(pts[i].x, pts[i].y), 6, c, cv::FILLED, cv::LINE_AA);
    cv::circle(img, cv::Point(legendX, legendY), 6, c, cv::FILLED, cv::LINE_AA);
    cv::putText(img, pts[i].label + " " + fmtNum(pts[i].y, 1), cv::Point(legendX + 12, legendY + 5),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1, cv::LINE_AA);
    legendY += 22;
  }
  if (std::isfinite(floorError)) {
    const cv::Scalar c(120, 120, 120);
    for (int x = px(x0, floorError).x; x < px(x1, floorError).x; x += 12)
      cv::line(img, cv::Point(x, px(x0, floorError).y), cv::Point(x + 6, px(x0, floorError).y), c,
               1, cv::LINE_AA);
    cv::line(img, cv::Point(legendX - 8, legendY), cv::Point(legendX + 8, legendY), c, 1,
             cv::LINE_AA);
    cv::putText(img, "true twin " + fmtNum(floorError, 1), cv::Point(legendX + 12, legendY + 5),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1, cv::LINE_AA);
  }
  cv::imwrite(file.string(), img);
}

}  // namespace

int main(int argc, char** argv) {
  std::string caseName = "case";
  fs::path plotFile;
  std::vector<Method> methods;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--case" && i + 1 < argc)
      caseName = argv[++i];
    else if (a == "--plot" && i + 1 < argc)
      plotFile = argv[++i];
    else if (a.find('=') != std::string::npos) {
      Method m;
      const size_t e1 = a.find('=');
      m.name = a.substr(0, e1);
      std::string rest = a.substr(e1 + 1);
      const size_t e2 = rest.rfind('=');
      if (e2 != std::string::npos) {
        m.wall = std::atof(rest.substr(e2 + 1).c_str());
        rest = rest.substr(0, e2);
      }
      m.dir = rest;
      methods.push_back(m);
    } else {
      std::fprintf(stderr,
                   "usage: %s --case NAME [--plot FILE.png] METHOD=OUT_DIR[=WALL_SECONDS]...\n",
                   argv[0]);
      return 2;
    }
  }
  // Stages in pipeline order (metrics.json objects are sorted by name), unknown ones after.
  const std::vector<std::string> order = {"geometry",
                                          "align",
                                          "lights0",
                                          "incident0",
                                          "select",
                                          "fit",
                                          "lights1",
                                          "incident1",
                                          "refine",
                                          "baseline-pixel-median",
                                          "baseline-shading-median",
                                          "export",
                                          "metrics",
                                          "report"};
  std::vector<std::string> stageNames;
  for (Method& m : methods) load(m);
  for (const auto& s : order)
    if (std::any_of(methods.begin(), methods.end(),
                    [&](const Method& m) { return m.stages.count(s) > 0; }))
      stageNames.push_back(s);
  for (const Method& m : methods)
    for (const auto& [k, v] : m.stages)
      if (std::find(stageNames.begin(), stageNames.end(), k) == stageNames.end())
        stageNames.push_back(k);
  std::cout << "### " << caseName << "\n\n| method |";
  for (const auto& s : stageNames) std::cout << " " << s << " s |";
  std::cout << " total s (w/o metrics) | view RMSE | view SSIM | view GMSD | novel RMSE | relit "
               "RMSE |\n|---|";
  for (size_t i = 0; i < stageNames.size() + 6; ++i) std::cout << "---|";
  std::cout << "\n";
  for (const Method& m : methods) {
    std::cout << "| " << m.name << " |";
    if (!m.ok) {
      for (size_t i = 0; i < stageNames.size(); ++i) std::cout << " |";
      std::cout << " " << fmtNum(m.wall, 1) << " | failed | | | | |\n";
      continue;
    }
    for (const auto& s : stageNames) {
      const auto it = m.stages.find(s);
      std::cout << " " << (it == m.stages.end() ? "-" : fmtNum(it->second, 1)) << " |";
    }
    std::cout << " " << fmtNum(m.total, 1) << " | " << fmtNum(m.viewRmse, 2) << " | "
              << fmtNum(m.viewSsim, 3) << " | " << fmtNum(m.viewGmsd, 3) << " | "
              << fmtNum(m.novelRmse, 2) << " | " << fmtNum(m.relitRmse, 2) << " |\n";
  }
  std::cout << "\nRMSE, SSIM and GMSD on the sRGB 8-bit scale (metrics.json color_spaces.srgb255); "
               "novel and relit: "
               "mean over the case's ground-truth renders.\n";
  if (!plotFile.empty()) {
    plot(methods, caseName, plotFile);
    std::cout << "plot: " << plotFile.string() << "\n";
  }
  std::cout.flush();
  return 0;
}
