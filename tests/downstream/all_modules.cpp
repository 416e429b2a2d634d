// Links every module of an installed photoscene (the pipeline pulls in all of them) and checks
// what the installed tree finds at run time.
//
//   all_modules [expected viewer folder]
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <photoscene/pipeline.hpp>
#include <photoscene/report.hpp>

int main(int argc, char** argv) {
  const char* baseline = ps::baselineName(ps::parseBaseline("shading-median"));
  std::printf("baseline: %s\n", baseline);
  if (std::strcmp(baseline, "shading-median") != 0) {
    std::fprintf(stderr, "FAILED: baseline name round trip\n");
    return 1;
  }
  const std::filesystem::path viewer = ps::defaultViewerDir();
  std::printf("viewer: %s\n", viewer.empty() ? "(none)" : viewer.c_str());
  if (argc > 1 && (viewer.empty() || !std::filesystem::equivalent(viewer, argv[1]))) {
    std::fprintf(stderr, "FAILED: the report's viewer is not the installed one (%s)\n", argv[1]);
    return 1;
  }
  std::printf("ok\n");
  return 0;
}
