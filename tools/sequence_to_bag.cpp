// Converts a recorded RGB-D sequence folder (layout: evaluation/rgbd_sequence.hpp, e.g.
// ../shared/data/real/visp_rbt) into a bag (topics: simulation/sequence_bag.hpp) that `evaluate`
// replays with --odom-frame map --base-frame camera_color_optical_frame --localization external.
//
//   rosrun scene_graph_tracker sequence_to_bag --sequence DIR --output OUT.bag [--rate HZ]
//       [--objects a,b] [--sigma-t M] [--sigma-r-deg DEG] [--miss P] [--seed N] [--compressed]
//       [--plane-map OUT.ply] [--quiet]
// --plane-map also writes the largest plane of the first frame's depth (RANSAC; the table the
// objects stand on) as a 4 m square map mesh in the map frame: the optional plane map of
// `make real`.
#include <Eigen/Geometry>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/simulation/sequence_bag.hpp"
#include "scene_graph_tracker/util/progress_bar.hpp"

namespace {

struct Args {
  std::string sequence, output, plane_map;
  sgt::ros::SequenceBagOptions bag;
  bool quiet = false;
};

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

Args parse(int argc, char** argv) {
  const sgt::cli::Flags flags(
      "sequence_to_bag",
      "--sequence DIR --output OUT.bag [--rate HZ] [--objects a,b] [--sigma-t M] "
      "[--sigma-r-deg DEG] [--miss P] [--seed N] [--compressed] [--plane-map OUT.ply] [--quiet]");
  Args a;
  flags.parse(argc, argv, [&](const std::string& k, const std::function<std::string()>& value) {
    if (k == "--sequence")
      a.sequence = value();
    else if (k == "--output")
      a.output = value();
    else if (k == "--rate")
      a.bag.rate_hz = std::stod(value());
    else if (k == "--objects")
      a.bag.objects = splitList(value());
    else if (k == "--sigma-t")
      a.bag.sigma_t = std::stod(value());
    else if (k == "--sigma-r-deg")
      a.bag.sigma_r_deg = std::stod(value());
    else if (k == "--miss")
      a.bag.miss_probability = std::stod(value());
    else if (k == "--seed")
      a.bag.seed = static_cast<std::uint32_t>(std::stoul(value()));
    else if (k == "--compressed")
      a.bag.compressed = true;
    else if (k == "--plane-map")
      a.plane_map = value();
    else if (k == "--quiet")
      a.quiet = true;
    else
      return false;
    return true;
  });
  if (a.sequence.empty() || a.output.empty()) flags.fail("--sequence and --output are required");
  return a;
}

// The plane (unit normal n, offset d: n.p + d = 0, n towards the camera) with the most depth
// points within 1 cm, by RANSAC over the first frame's points in the map frame.
Eigen::Vector4d largestPlane(const sgt::RgbdSequence& s) {
  const auto& f = s.frames.front();
  const std::vector<float> depth = sgt::loadSequenceDepth(s, f);
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < s.camera.height; v += 4)
    for (int u = 0; u < s.camera.width; u += 4) {
      const float z = depth[static_cast<std::size_t>(v) * s.camera.width + u];
      if (std::isfinite(z))
        points.push_back(f.T_map_camera * Eigen::Vector3d((u - s.camera.cx) / s.camera.fx * z,
                                                          (v - s.camera.cy) / s.camera.fy * z, z));
    }
  if (points.size() < 3) throw sgt::SequenceError(f.depth_path + ": too few depth points");
  std::mt19937 rng(1);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  Eigen::Vector4d best(0, 0, 1, 0);
  std::size_t best_count = 0;
  for (int it = 0; it < 500; ++it) {
    const Eigen::Vector3d a = points[pick(rng)], b = points[pick(rng)], c = points[pick(rng)];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    const Eigen::Vector3d u = n.normalized();
    std::size_t count = 0;
    for (const Eigen::Vector3d& p : points) count += std::abs(u.dot(p - a)) < 0.01;
    if (count > best_count) best_count = count, best << u, -u.dot(a);
  }
  if (best.head<3>().dot(f.T_map_camera.translation()) + best.w() < 0) best = -best;
  return best;
}

// A 4 m square of the plane, centred under the first camera, facing it.
void writePlaneMap(const sgt::RgbdSequence& s, const std::string& path) {
  const Eigen::Vector4d plane = largestPlane(s);
  const Eigen::Vector3d n = plane.head<3>();
  const Eigen::Vector3d cam = s.frames.front().T_map_camera.translation();
  const Eigen::Vector3d centre = cam - (n.dot(cam) + plane.w()) * n;
  const Eigen::Vector3d u = n.unitOrthogonal() * 4.0, v = n.cross(u.normalized()) * 4.0;
  sgt::TriangleMesh mesh;
  sgt::appendQuadGrid(mesh, (centre - 0.5 * u - 0.5 * v).cast<float>(), u.cast<float>(),
                      v.cast<float>(), 40, 40);
  sgt::savePly(mesh, path);
  std::cerr << "sequence_to_bag: plane map " << path << ": normal " << n.transpose() << ", offset "
            << plane.w() << " m\n";
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse(argc, argv);
  try {
    const sgt::RgbdSequence sequence = sgt::loadRgbdSequence(args.sequence);
    sgt::ProgressBar progress("sequence_to_bag", sequence.frames.size());
    const auto summary = sgt::ros::writeSequenceBag(sequence, args.output, args.bag,
                                                    [&](std::size_t done, std::size_t) {
                                                      if (!args.quiet) progress.update(done);
                                                    });
    if (!args.quiet) progress.finish();
    if (!args.plane_map.empty()) writePlaneMap(sequence, args.plane_map);
    std::cerr << "sequence_to_bag: " << args.output << ": " << summary.frames << " frames, "
              << summary.hypotheses << " hypotheses\n";
  } catch (const std::exception& e) {
    std::cerr << "sequence_to_bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
