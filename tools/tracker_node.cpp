// The tracker as a plain node: TrackerNodelet in its own process.
#include "nodelet_main.hpp"

int main(int argc, char** argv) {
  return sgt::cli::runNodelet(argc, argv, "tracker", "scene_graph_tracker/TrackerNodelet");
}
