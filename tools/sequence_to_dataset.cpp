// Writes a recorded RGB-D sequence (layout: evaluation/rgbd_sequence.hpp, e.g.
// ../shared/data/real/visp_rbt) as a keypoint data set (evaluation/keypoint_dataset.hpp), labelled
// from the sequence's given object poses, so that evaluate_detector scores a detector on real
// images: detection rate, keypoint error and PnP pose error against the given poses. The depth goes
// along (depth/, millimetres), so that the PnP poses take their distance from it as in the nodes.
//
//   rosrun scene_graph_tracker sequence_to_dataset --sequence DIR --catalog FILE --output OUT
//       [--mesh-dir D] [--labels object|cuboid|shape]   (detection/label_kind.hpp)
//
// Class ids and boxes: SequenceLabeller (evaluation/keypoint_dataset.hpp).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "command_line.hpp"
#include "scene_graph_tracker/evaluation/keypoint_dataset.hpp"
#include "scene_graph_tracker/evaluation/rgbd_sequence.hpp"
#include "scene_graph_tracker/util/progress_bar.hpp"

namespace fs = std::filesystem;

namespace {

struct Args {
  std::string sequence, catalog, output, mesh_dir, labels = "object";
};

Args parse(int argc, char** argv) {
  const sgt::cli::Flags flags("sequence_to_dataset",
                              "--sequence DIR --catalog FILE --output OUT [--mesh-dir D] "
                              "[--labels object|cuboid|shape]");
  Args a;
  flags.parse(argc, argv,
              {{"--sequence", &a.sequence},
               {"--catalog", &a.catalog},
               {"--output", &a.output},
               {"--mesh-dir", &a.mesh_dir},
               {"--labels", &a.labels}});
  if (a.sequence.empty() || a.catalog.empty() || a.output.empty())
    flags.fail("--sequence, --catalog and --output are required");
  if (!sgt::detection::parseLabelKind(a.labels)) flags.fail("--labels is object, cuboid or shape");
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse(argc, argv);
  try {
    const sgt::RgbdSequence sequence = sgt::loadRgbdSequence(args.sequence);
    const sgt::ObjectCatalog catalog = sgt::loadObjectCatalog(args.catalog, args.mesh_dir);
    const fs::path dir = fs::absolute(args.output);
    for (const char* sub : {"images", "labels", "poses", "depth"})
      fs::create_directories(dir / sub);
    sgt::SequenceLabeller labeller(catalog, sequence, *sgt::detection::parseLabelKind(args.labels));
    sgt::ProgressBar bar("sequence_to_dataset", sequence.frames.size());
    for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
      const auto& f = sequence.frames[i];
      cv::Mat bgr;
      cv::cvtColor(sgt::loadSequenceRgb(sequence, f), bgr, cv::COLOR_RGB2BGR);
      const std::string name = sgt::datasetFrameName(i) + ".png";
      cv::imwrite((dir / "images" / name).string(), bgr);
      sgt::writeDatasetDepth(dir, i, sgt::loadSequenceDepth(sequence, f), sequence.camera.width,
                             sequence.camera.height);
      sgt::writeDatasetLabels(dir, i, "real", sequence.camera, labeller.label(f));
      bar.update(i + 1);
    }
    bar.finish();
    sgt::writeDatasetYaml(dir,
                          "sequence_to_dataset --sequence " + args.sequence + " --catalog " +
                              args.catalog + " --labels " + args.labels,
                          catalog.listed());
  } catch (const std::exception& e) {
    std::cerr << "sequence_to_dataset: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
