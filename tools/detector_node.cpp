// The detector as a plain node: DetectorNodelet in its own process.
#include "nodelet_main.hpp"

int main(int argc, char** argv) {
  return sgt::cli::runNodelet(argc, argv, "detector", "scene_graph_tracker/DetectorNodelet");
}
