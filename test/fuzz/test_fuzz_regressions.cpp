// The fuzz targets' bodies (test/fuzz/fuzz_targets.hpp) on every file of their seed corpora
// (test/fuzz/corpus/<name>/) and of the inputs that once found a defect
// (test/fuzz/regressions/<name>/): none may crash, trip an expectation of its body (abort) or
// throw. `make fuzz` runs the same bodies under libFuzzer with ASan and UBSan.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_targets.hpp"

namespace {

namespace fs = std::filesystem;
using Body = int (*)(const std::uint8_t*, std::size_t);

std::vector<std::uint8_t> readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in),
                                   std::istreambuf_iterator<char>());
}

// Runs every file of the target's corpus and regression directories; how many there were.
std::size_t replay(const std::string& target, Body body) {
  std::vector<fs::path> files;
  for (const char* set : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(SGT_SOURCE_DIR) / "test" / "fuzz" / set / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const std::vector<std::uint8_t> bytes = readAll(f);
    EXPECT_NO_THROW(body(bytes.data(), bytes.size()));
  }
  return files.size();
}

TEST(FuzzRegressions, Cloud) { EXPECT_GT(replay("cloud", sgtFuzzCloud), 0u); }
TEST(FuzzRegressions, Images) { EXPECT_GT(replay("images", sgtFuzzImages), 0u); }
TEST(FuzzRegressions, Hypotheses) { EXPECT_GT(replay("hypotheses", sgtFuzzHypotheses), 0u); }
TEST(FuzzRegressions, YoloPose) { EXPECT_GT(replay("yolo_pose", sgtFuzzYoloPose), 0u); }
TEST(FuzzRegressions, Mesh) { EXPECT_GT(replay("mesh", sgtFuzzMesh), 0u); }
TEST(FuzzRegressions, Config) { EXPECT_GT(replay("config", sgtFuzzConfig), 0u); }
TEST(FuzzRegressions, SemapBridge) { EXPECT_GT(replay("semap_bridge", sgtFuzzSemapBridge), 0u); }

}  // namespace
