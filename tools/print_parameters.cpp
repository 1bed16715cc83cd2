// The files generated from the parameter schema (pipeline/parameter_schema.hpp).
//   print_parameters --write DIR   rewrites config/tracker.yaml, config/detector.yaml,
//   cfg/Tracker.cfg,
//                                  doc/parameters.md and the README's index under DIR, the package
//                                  source (`make params`); says which ones changed
//   print_parameters WHAT          prints one: tracker-yaml, detector-yaml, tracker-cfg,
//                                  tracker-tables, detector-tables, reference
// test_parameter_schema fails while a committed copy differs from what this writes.
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>

#include "scene_graph_tracker/pipeline/parameter_schema.hpp"

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Writes only when the text differs (the file keeps its mode, e.g. the .cfg's executable bit).
void update(const std::string& path, const std::string& text) {
  if (std::ifstream(path) && read(path) == text) return;
  std::ofstream out(path, std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
  std::cout << "updated " << path << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sgt::params;
  const std::map<std::string, std::function<std::string()>> files = {
      {"tracker-yaml", trackerYaml},       {"detector-yaml", detectorYaml},
      {"tracker-cfg", trackerReconfigure}, {"tracker-tables", trackerTables},
      {"detector-tables", detectorTables}, {"reference", parameterReference},
  };
  const std::string usage =
      "usage: print_parameters --write PACKAGE_DIR | tracker-yaml | detector-yaml | tracker-cfg | "
      "tracker-tables | detector-tables | reference\n";
  try {
    if (argc == 3 && std::string(argv[1]) == "--write") {
      const std::string dir = argv[2];
      update(dir + "/config/tracker.yaml", trackerYaml());
      update(dir + "/config/detector.yaml", detectorYaml());
      update(dir + "/cfg/Tracker.cfg", trackerReconfigure());
      update(dir + "/doc/parameters.md", parameterReference());
      std::string readme = read(dir + "/README.md");
      readme = replaceGeneratedSection(readme, "tracker parameters", trackerIndex());
      readme = replaceGeneratedSection(readme, "detector parameters", detectorIndex());
      update(dir + "/README.md", readme);
      return 0;
    }
    if (argc == 2 && files.count(argv[1])) {
      std::cout << files.at(argv[1])();
      return 0;
    }
  } catch (const std::exception& e) {
    std::cerr << "print_parameters: " << e.what() << "\n";
    return 1;
  }
  std::cerr << usage;
  return 2;
}
