// Writes N generated scenarios (simulation/scenario_generator.hpp) for the suite:
//
//   rosrun scene_graph_tracker generate_scenarios --count N --seed S --output DIR
//       [--catalog FILE] [--mesh-dir DIR] [--duration SECONDS]
//
// DIR/scenario_NNN.yaml for NNN = 001..N, each checked by loading it as `simulate` does, and
// DIR/scenarios.yaml, the index: per scenario its file, seed, what it holds (kinds), object count,
// depth-noise factor, odometry start error, detector miss rate and false positives. The same
// arguments give the same files.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

#include "command_line.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/simulation/scenario_generator.hpp"

namespace {

std::uint32_t scenarioSeed(std::uint32_t seed, int index) {
  std::seed_seq sequence{seed, static_cast<std::uint32_t>(index)};
  std::uint32_t out = 0;
  sequence.generate(&out, &out + 1);
  return out;
}

void indexEntry(YAML::Emitter& index, const sgt::sim::GeneratedScenario& g,
                const std::string& file) {
  index << YAML::BeginMap << YAML::Key << "name" << YAML::Value << g.name << YAML::Key << "file"
        << YAML::Value << file << YAML::Key << "seed" << YAML::Value << g.seed << YAML::Key
        << "kinds" << YAML::Value << YAML::Flow << g.kinds << YAML::Key << "objects" << YAML::Value
        << g.objects.size() << YAML::Key << "depth_noise_factor" << YAML::Value << g.noise_factor
        << YAML::Key << "odometry_error_m" << YAML::Value << g.odometry_error.head<2>().norm()
        << YAML::Key << "odometry_error_deg" << YAML::Value
        << std::abs(g.odometry_error.z()) * 180.0 / M_PI << YAML::Key << "miss_probability"
        << YAML::Value << g.miss_probability << YAML::Key << "false_positives_per_frame"
        << YAML::Value << g.false_positives << YAML::Key << "hidden_fraction" << YAML::Value
        << g.hidden_fraction << YAML::EndMap;
}

struct Args {
  sgt::sim::GeneratorOptions options;
  int count = 0;
  std::uint32_t seed = 1;
  std::string output;
};

Args parse(int argc, char** argv) {
  const sgt::cli::Flags flags("generate_scenarios",
                              "--count N --seed S --output DIR [--catalog FILE] [--mesh-dir DIR] "
                              "[--duration SECONDS]");
  Args a;
  flags.parse(argc, argv, [&](const std::string& k, const std::function<std::string()>& value) {
    if (k == "--count")
      a.count = std::stoi(value());
    else if (k == "--seed")
      a.seed = static_cast<std::uint32_t>(std::stoul(value()));
    else if (k == "--output")
      a.output = value();
    else if (k == "--catalog")
      a.options.catalog = value();
    else if (k == "--mesh-dir")
      a.options.mesh_dir = std::filesystem::absolute(value()).string();
    else if (k == "--duration")
      a.options.duration = std::stod(value());
    else
      return false;
    return true;
  });
  if (a.count <= 0 || a.output.empty()) flags.fail("--count (> 0) and --output are required");
  return a;
}

// Writes scenario i as OUTPUT/scenario_NNN.yaml, checks that it loads, adds it to the index.
void writeOne(const Args& a, const std::map<std::string, sgt::sim::ClassShape>& shapes, int i,
              YAML::Emitter& index) {
  std::ostringstream name;
  name << "scenario_" << std::setw(3) << std::setfill('0') << i;
  const auto g = sgt::sim::generateScenario(a.options, shapes, scenarioSeed(a.seed, i), name.str());
  const std::string file = name.str() + ".yaml", path = a.output + "/" + file;
  {
    std::ofstream out(path);
    sgt::sim::writeScenarioYaml(g, a.options, out);
  }
  sgt::sim::loadScenario(path);  // throws on anything simulate would refuse
  indexEntry(index, g, file);
  std::cout << "[" << i << "/" << a.count << "] " << path << ": " << g.objects.size()
            << " objects, " << g.distractors.size() << " unknown things\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sgt;
  const Args a = parse(argc, argv);
  try {
    const ObjectCatalog catalog =
        loadObjectCatalog(resolveResourcePath(a.options.catalog), a.options.mesh_dir);
    const auto shapes = sim::classShapes(catalog);
    for (const auto& [name, s] : shapes)
      if (s.container)
        std::cout << name << ": a container (floor " << s.floor << " m, inner half extents "
                  << s.inner_half.transpose() << " m)\n";
    std::filesystem::create_directories(a.output);
    YAML::Emitter index;
    index << YAML::BeginMap << YAML::Key << "seed" << YAML::Value << a.seed << YAML::Key
          << "scenarios" << YAML::Value << YAML::BeginSeq;
    for (int i = 1; i <= a.count; ++i) writeOne(a, shapes, i, index);
    index << YAML::EndSeq << YAML::EndMap;
    std::ofstream(a.output + "/scenarios.yaml") << index.c_str() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "generate_scenarios: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
