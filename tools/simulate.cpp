// Simulates a scenario into a rosbag with ground truth (topics:
// include/scene_graph_tracker/simulation/scenario_bag.hpp, scenario format: README.md "Scenario
// format").
//
//   rosrun scene_graph_tracker simulate --scenario FILE.yaml --output OUT.bag [--mesh-dir DIR]
//   [--duration S] [--lz4] [--quiet]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "scene_graph_tracker/simulation/scenario_bag.hpp"

namespace {

void usage(std::ostream& os) {
  os << "usage: simulate --scenario FILE.yaml --output OUT.bag [--mesh-dir DIR] [--duration S] "
        "[--lz4] [--quiet]\n"
        "  --scenario  the scenario (format: README.md, \"Scenario format\")\n"
        "  --output    the bag to write (overwritten)\n"
        "  --mesh-dir  use the meshes in DIR for the catalog classes (e.g. "
        "../shared/data/pbr_objects/meshes),\n"
        "              replacing the scenario's mesh_dir\n"
        "  --duration  only the scenario's first S seconds\n"
        "  --lz4       compress the bag with LZ4\n"
        "  --quiet     no progress bar\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_path, output, mesh_dir;
  double duration = 0.0;  // > 0: the scenario's first seconds only
  bool lz4 = false, quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "simulate: " << a << " needs a value\n";
        usage(std::cerr);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--scenario")
      scenario_path = value();
    else if (a == "--output")
      output = value();
    else if (a == "--mesh-dir")
      mesh_dir = value();
    else if (a == "--duration")
      duration = std::stod(value());
    else if (a == "--lz4")
      lz4 = true;
    else if (a == "--quiet")
      quiet = true;
    else if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    } else {
      std::cerr << "simulate: unknown argument '" << a << "'\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (scenario_path.empty() || output.empty()) {
    usage(std::cerr);
    return 2;
  }

  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  try {
    sgt::sim::ScenarioLoadOptions load;
    load.mesh_dir_override = mesh_dir;
    sgt::sim::Scenario scenario = sgt::sim::loadScenario(scenario_path, load);
    if (duration > 0.0) scenario.duration = std::min(scenario.duration, duration);
    if (!quiet)
      std::cerr << "simulate: " << scenario_path << ": " << scenario.duration << " s, "
                << scenario.objects.size() << " objects, " << scenario.distractors.size()
                << " distractors, static map " << scenario.static_map->triangleCount()
                << " triangles (loaded in " << seconds() << " s)\n";
    sgt::ros::ScenarioBagOptions options;
    options.lz4 = lz4;
    int last_percent = -1;
    const auto progress = [&](std::size_t done, std::size_t total) {
      const int percent = static_cast<int>(100 * done / total);
      if (percent == last_percent && done != total) return;
      last_percent = percent;
      const int width = 40, filled = width * percent / 100;
      const double elapsed = seconds();
      std::fprintf(stderr, "\r[%s%s] %3d%%  %zu/%zu stamps  %.1f s",
                   std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
                   percent, done, total, elapsed);
      if (done == total) std::fputc('\n', stderr);
      std::fflush(stderr);
    };
    const auto summary = sgt::ros::writeScenarioBag(
        scenario, output, quiet ? sgt::ros::ProgressCallback() : progress, options);
    const double mb = static_cast<double>(std::filesystem::file_size(output)) / 1e6;
    std::cerr << "simulate: wrote " << output << " (" << summary.camera_frames << " camera frames, "
              << summary.lidar_scans << " LiDAR scans, " << summary.hypotheses << " hypotheses, "
              << mb << " MB) in " << seconds() << " s\n";
  } catch (const std::exception& e) {
    std::cerr << "simulate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
