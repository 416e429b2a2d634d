#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <limits>
#include <vector>

#include "photoscene/core.hpp"
#include "photoscene/core/data_folder.hpp"
#include "photoscene/core/memory.hpp"

namespace ps {
namespace {

TEST(Core_Srgb, round_trip_every_8bit_value_within_one_level) {
  for (int v = 0; v < 256; ++v) {
    const float lin = srgbToLinear(v / 255.0f);
    // the contract asks for 1/255; the exact curve gives far better (half a level is rounding)
    EXPECT_NEAR(linearToSrgb(lin), v / 255.0f, 0.5f / 255.0f) << "value " << v;
  }
}

TEST(Core_Srgb, image_round_trip_is_exact_for_8bit) {
  cv::Mat u8(1, 256, CV_8UC3);
  for (int i = 0; i < 256; ++i) u8.at<cv::Vec3b>(0, i) = cv::Vec3b(i, 255 - i, i / 2);
  const cv::Mat lin = srgbToLinear(u8);
  ASSERT_EQ(lin.type(), CV_32FC3);
  const cv::Mat back = linearToSrgb(lin, CV_8U);
  EXPECT_EQ(cv::norm(u8, back, cv::NORM_INF), 0.0);
}

TEST(Core_Srgb, matches_the_piecewise_definition) {
  // Reference points of IEC 61966-2-1.
  EXPECT_NEAR(srgbToLinear(0.04045f), 0.04045f / 12.92f, 1e-7);
  EXPECT_NEAR(srgbToLinear(0.5f), 0.214041140f, 1e-6);
  EXPECT_NEAR(srgbToLinear(1.0f), 1.0f, 1e-7);
  EXPECT_NEAR(linearToSrgb(0.214041140f), 0.5f, 1e-6);
  EXPECT_EQ(linearToSrgb(-1.0f), 0.0f);
  EXPECT_EQ(linearToSrgb(7.0f), 1.0f);
}

TEST(Core_Srgb, sixteen_bit_round_trip) {
  for (int v = 0; v < 65536; v += 97) {
    const float lin = srgbToLinear(v / 65535.0f);
    EXPECT_NEAR(linearToSrgb(lin) * 65535.0f, v, 0.5f) << v;
  }
}

TEST(Core_Error, binary_checks_print_both_values) {
  try {
    const int a = 3, b = 4;
    PS_CheckEQ(a, b, "sizes differ");
    FAIL() << "no throw";
  } catch (const Exception& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("(3 vs 4)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sizes differ"), std::string::npos) << msg;
    EXPECT_NE(msg.find("test_core.cpp"), std::string::npos) << msg;
  }
  EXPECT_NO_THROW(PS_CheckLT(1, 2, ""));
  EXPECT_THROW(PS_CheckGE(1, 2, ""), Exception);
  EXPECT_THROW(PS_Assert(1 + 1 == 3), Exception);
}

TEST(Core_Error, input_error_names_file_key_and_expectation) {
  const InputError e("scene.json", "views[0].camera.fx", "expected a positive number, got -3");
  EXPECT_STREQ(e.what(), "scene.json: views[0].camera.fx: expected a positive number, got -3");
  EXPECT_EQ(e.file(), "scene.json");
}

TEST(Core_Image, check_image_reports_types) {
  cv::Mat m(4, 4, CV_8UC1);
  try {
    checkImage(m, CV_32FC3, "photo");
    FAIL();
  } catch (const Exception& e) {
    EXPECT_NE(std::string(e.what()).find("CV_32FC3"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("CV_8UC1"), std::string::npos);
  }
  cv::Mat f(2, 2, CV_32FC1, cv::Scalar(1.0));
  EXPECT_TRUE(allFinite(f));
  f.at<float>(1, 1) = std::nanf("");
  EXPECT_FALSE(allFinite(f));
}

TEST(Core_Image, periodic_sample_is_bilinear_and_wraps_on_both_axes) {
  // a 5 x 3 map (not square, odd): texel centres return the texel, the seam between the last and
  // the first column (row) is the mean of the two, and any whole period added to (u, v), negative
  // too, returns the same value
  const int n = 5, m = 3;
  cv::Mat map(m, n, CV_32FC3);
  Rng rng(11);
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < n; ++x)
      map.at<cv::Vec3f>(y, x) =
          cv::Vec3f(rng.uniform(0.f, 1.f), rng.uniform(0.f, 1.f), rng.uniform(0.f, 1.f));
  auto texel = [&](int x, int y) { return map.at<cv::Vec3f>(y, x); };
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < n; ++x) {
      const float u = (x + 0.5f) / n, v = 1.0f - (y + 0.5f) / m;
      EXPECT_LT(cv::norm(samplePeriodic(map, u, v) - texel(x, y)), 1e-6) << x << ", " << y;
    }
  const float v0 = 1.0f - 0.5f / m;  // the centre of row 0
  EXPECT_LT(cv::norm(samplePeriodic(map, 1.0f, v0) - 0.5f * (texel(n - 1, 0) + texel(0, 0))), 1e-6);
  EXPECT_LT(cv::norm(samplePeriodic(map, 0.0f, v0) - 0.5f * (texel(n - 1, 0) + texel(0, 0))), 1e-6);
  const float u0 = 0.5f / n;  // the centre of column 0; v = 0 is the seam of the last and first row
  EXPECT_LT(cv::norm(samplePeriodic(map, u0, 0.0f) - 0.5f * (texel(0, m - 1) + texel(0, 0))), 1e-6);
  for (int i = 0; i < 200; ++i) {
    const float u = rng.uniform(0.f, 1.f), v = rng.uniform(0.f, 1.f);
    const cv::Vec3f ref = samplePeriodic(map, u, v);
    for (int k : {-3, -1, 1, 2}) {
      EXPECT_LT(cv::norm(samplePeriodic(map, u + k, v) - ref), 1e-4) << u << " + " << k;
      EXPECT_LT(cv::norm(samplePeriodic(map, u, v + k) - ref), 1e-4) << v << " + " << k;
    }
  }
}

TEST(Core_Rng, same_seed_same_sequence_and_split_is_stable) {
  Rng a(42), b(42), c(43);
  bool anyDiff = false;
  for (int i = 0; i < 100; ++i) {
    const uint32_t x = a.nextU32();
    EXPECT_EQ(x, b.nextU32());
    anyDiff |= x != c.nextU32();
  }
  EXPECT_TRUE(anyDiff);
  // split does not depend on how far the parent advanced
  Rng p(7);
  const uint32_t s0 = p.split(5).nextU32();
  p.nextU32();
  EXPECT_EQ(s0, p.split(5).nextU32());
  EXPECT_NE(p.split(5).nextU32(), p.split(6).nextU32());
}

TEST(Core_Rng, uniform_moments_and_range) {
  Rng rng(1);
  double sum = 0, sum2 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const float u = rng.uniform();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    sum += u;
    sum2 += u * u;
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
  EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12.0, 0.002);
  std::vector<int> hist(7, 0);
  for (int i = 0; i < 70000; ++i) hist[rng.uniformInt(7)]++;
  for (int h : hist) EXPECT_NEAR(h, 10000, 500);
  double ns = 0, ns2 = 0;
  for (int i = 0; i < n; ++i) {
    const double g = rng.normal();
    ASSERT_TRUE(std::isfinite(g));
    ns += g;
    ns2 += g * g;
  }
  EXPECT_NEAR(ns / n, 0.0, 0.01);
  EXPECT_NEAR(ns2 / n, 1.0, 0.02);
}

TEST(Core_Parallel, covers_every_index_once_for_any_thread_count) {
  for (int threads : {1, 2, 4}) {
    ThreadLimit limit(threads);
    std::vector<std::atomic<int>> hits(1000);
    parallelFor(0, 1000, [&](int64_t i) { hits[i]++; }, 7);
    for (auto& h : hits) ASSERT_EQ(h.load(), 1);
    EXPECT_LE(maxThreads(), threads);
  }
}

TEST(Core_Parallel, seeded_parallel_work_is_thread_count_independent) {
  auto run = [](int threads) {
    ThreadLimit limit(threads);
    std::vector<float> out(4096);
    Rng root(99);
    parallelFor(0, 4096, [&](int64_t i) { out[i] = root.split(i).uniform(); }, 16);
    return out;
  };
  EXPECT_EQ(run(1), run(2));
}

TEST(Core_Progress, counts_from_many_threads) {
  Progress progress("test", 500, ProgressOptions{ProgressOptions::Mode::Silent});
  parallelFor(0, 500, [&](int64_t) { progress.advance(); });
  progress.finish();
  EXPECT_EQ(progress.done(), 500);
  Progress logged("logged", 3, ProgressOptions{ProgressOptions::Mode::Log});
  logged.advance(3);
  EXPECT_EQ(logged.mode(), ProgressOptions::Mode::Log);
}

TEST(Core_Hasher, content_changes_change_the_digest) {
  const uint64_t a = Hasher().add(std::string_view("abc")).add(1.5f).digest();
  const uint64_t b = Hasher().add(std::string_view("abc")).add(1.5f).digest();
  const uint64_t c = Hasher().add(std::string_view("abd")).add(1.5f).digest();
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(Core_Math, wrap_index_is_the_texel_of_a_tiling_map) {
  // every i lands in [0, n) and i, i + n, i - n land on the same texel, across zero and far out
  for (int n : {1, 2, 5, 64}) {
    for (int i = -3 * n - 2; i <= 3 * n + 2; ++i) {
      const int w = wrapIndex(i, n);
      ASSERT_GE(w, 0) << i << " mod " << n;
      ASSERT_LT(w, n) << i << " mod " << n;
      EXPECT_EQ(w, wrapIndex(i + n, n));
      EXPECT_EQ((i - w) % n, 0) << i << " mod " << n;
    }
  }
  EXPECT_EQ(wrapIndex(-1, 5), 4);
  EXPECT_EQ(wrapIndex(std::numeric_limits<int>::min(), 64), 0);
  EXPECT_EQ(wrapIndex(std::numeric_limits<int>::max(), 64), 63);
}

TEST(Core_Math, orthonormal_basis_is_orthonormal) {
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    Vec3f n(rng.normal(), rng.normal(), rng.normal());
    if (n.norm() < 1e-3f) continue;
    n.normalize();
    Vec3f t, b;
    orthonormalBasis(n, t, b);
    EXPECT_NEAR(t.norm(), 1.0f, 1e-5);
    EXPECT_NEAR(b.norm(), 1.0f, 1e-5);
    EXPECT_NEAR(t.dot(n), 0.0f, 1e-5);
    EXPECT_NEAR(b.dot(n), 0.0f, 1e-5);
    EXPECT_NEAR(t.cross(b).dot(n), 1.0f, 1e-4);
  }
}

}  // namespace
// Issue 9: SIGTERM takes the graceful path of SIGINT and is told apart (exit 143, not 130).
TEST(Core_Interrupt, sigterm_is_a_request_named_by_its_signal) {
  clearInterrupt();
  EXPECT_EQ(interruptSignal(), 0);
  {
    InterruptGuard guard;
    std::raise(SIGTERM);
    EXPECT_TRUE(interruptRequested());
    EXPECT_EQ(interruptSignal(), SIGTERM);
    try {
      checkInterrupted();
      ADD_FAILURE() << "checkInterrupted() did not throw";
    } catch (const Interrupted& e) {
      EXPECT_EQ(e.signal(), SIGTERM);
    }
  }
  clearInterrupt();
  requestInterrupt();
  EXPECT_EQ(interruptSignal(), SIGINT);
  clearInterrupt();
  EXPECT_FALSE(interruptRequested());
}

TEST(Core_Memory, peak_memory_grows_with_a_touched_allocation) {
  const int64_t before = peakMemoryBytes();
  EXPECT_GT(before, 0);
  std::vector<char> block(size_t(64) << 20, 1);  // 64 MiB, touched
  EXPECT_GE(peakMemoryBytes(), before + (int64_t(32) << 20) * (block[12345] == 1));
}

// An installed tree's data (<bin>/../share/photoscene/<name>) comes before the build tree's folder,
// which comes before nothing; a name found nowhere is empty.
TEST(Core_DataFolder, beside_the_program_then_the_build_tree) {
  namespace fs = std::filesystem;
  const fs::path bin = executableFolder();
  ASSERT_FALSE(bin.empty());
  EXPECT_TRUE(fs::equivalent(bin / "ps_test_core", fs::read_symlink("/proc/self/exe")));
  const std::string name = "core_data_folder_test";
  const fs::path buildTree = fs::path(PS_BINARY_DIR) / "core_data_folder_build_tree";
  const fs::path beside = bin / ".." / "share" / "photoscene" / name;
  fs::remove_all(beside);
  fs::create_directories(buildTree);
  EXPECT_TRUE(findDataFolder(name).empty());
  EXPECT_EQ(findDataFolder(name, buildTree), buildTree);
  EXPECT_TRUE(findDataFolder(name, buildTree / "missing").empty());
  fs::create_directories(beside);
  const fs::path found = findDataFolder(name, buildTree);
  EXPECT_TRUE(fs::equivalent(found, beside)) << found;
  EXPECT_EQ(found, found.lexically_normal());
  fs::remove_all(beside);
  fs::remove_all(buildTree);
}

}  // namespace ps
