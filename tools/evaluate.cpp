// Offline evaluation: runs the tracker's per-frame pipeline over a bag (no roscore) and, when the
// bag has ground truth, scores it.
//   rosrun scene_graph_tracker evaluate --bag IN.bag --output DIR
//       [--map building|FILE.urdf|FILE.ply] [--furniture FILE.yaml] [--catalog objects.yaml]
//       [--mesh-dir DIR] [--no-plots]
//       (--map building: the generated building with its workbench top as furniture, built here;
//        write_map writes it as files, the way the tracker nodelet takes it)
//       [--oracle-localization]   (robot pose from the bag's ground truth: objects scored alone)
//       [--detector MODEL.yaml|default]  (hypotheses from the keypoint detector on the bag's RGB
//                                         images instead of the bag's hypotheses topic)
//       [--scenario FILE.yaml]    (the bag's scenario: its declared relations are scored)
//       [--no-relations]          (no relations, hence no re-parenting: the tracker as before them)
//       [--params FILE]           (tracker parameters, as the nodelet reads them; default
//                                  config/tracker.yaml: offline and live runs use the same values)
//       [--detector-params FILE]  (detector parameters with --detector; default config/detector.yaml)
// Options: the structs' defaults, then the parameter files, then the flags: --oracle-localization
// turns localize off, --no-relations relations/enabled, and --detector turns search_orientations
// on (as tracker.launch sets it to its detector argument).
// Writes DIR/report.json, DIR/report.md, DIR/timeseries.csv and DIR/*.png, prints the table.
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include "command_line.hpp"
#include "scene_graph_tracker/detection/pose_detector.hpp"
#include "scene_graph_tracker/evaluation/pose_metrics.hpp"
#include "scene_graph_tracker/evaluation/report.hpp"
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/ros/bag_frames.hpp"
#include "scene_graph_tracker/scene/static_map.hpp"
#include "scene_graph_tracker/simulation/building_map.hpp"
#include "scene_graph_tracker/simulation/scenario.hpp"
#include "scene_graph_tracker/util/progress_bar.hpp"

namespace {

struct Args {
  std::string bag, output, map = "building", catalog = std::string(SGT_SOURCE_DIR) + "/config/objects.yaml", mesh_dir;
  std::string scenario;
  std::string furniture;  // furniture YAML (relations/furniture.hpp); replaces the building's workbench
  bool plots = true;
  bool oracle_localization = false;  // robot pose from the ground truth: scores objects alone
  std::string detector;              // model metadata YAML; empty: the bag's hypotheses
  bool relations = true;
  std::string params = std::string(SGT_SOURCE_DIR) + "/config/tracker.yaml";
  std::string detector_params = std::string(SGT_SOURCE_DIR) + "/config/detector.yaml";
};

Args parse(int argc, char** argv) {
  const sgt::cli::Flags flags("evaluate",
                              "--bag IN.bag --output DIR [--map building|FILE] [--furniture FILE] [--catalog FILE] "
                              "[--mesh-dir DIR] [--no-plots] [--oracle-localization] [--detector MODEL.yaml|default] "
                              "[--scenario FILE] [--no-relations] [--params FILE] [--detector-params FILE]");
  Args a;
  flags.parse(argc, argv, [&](const std::string& k, const std::function<std::string()>& value) {
    if (k == "--bag") a.bag = value();
    else if (k == "--output") a.output = value();
    else if (k == "--map") a.map = value();
    else if (k == "--furniture") a.furniture = value();
    else if (k == "--catalog") a.catalog = value();
    else if (k == "--mesh-dir") a.mesh_dir = value();
    else if (k == "--no-plots") a.plots = false;
    else if (k == "--oracle-localization") a.oracle_localization = true;
    else if (k == "--detector") a.detector = value();
    else if (k == "--scenario") a.scenario = value();
    else if (k == "--no-relations") a.relations = false;
    else if (k == "--params") a.params = value();
    else if (k == "--detector-params") a.detector_params = value();
    else return false;
    return true;
  });
  if (a.bag.empty() || a.output.empty()) flags.fail("--bag and --output are required");
  if (a.detector == "default") a.detector = std::string(SGT_SOURCE_DIR) + "/models/sgt_keypoints.yaml";
  return a;
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

// Whether an object's centre projects into the frame's depth image (the camera at its true pose:
// T_odom_camera of the depth set moved by the true map -> odom).
bool inView(const sgt::PipelineFrame& frame, const Eigen::Isometry3d& T_map_base_true, const Eigen::Isometry3d& T_map_object) {
  for (const sgt::RangeMeasurements& m : frame.measurements) {
    const auto* cam = std::get_if<sgt::PinholeModel>(&m.model);
    if (!cam) continue;
    const Eigen::Isometry3d T_map_camera = T_map_base_true * frame.T_odom_base.inverse() * m.T_world_sensor;
    const auto px = cam->project(T_map_camera.inverse() * T_map_object.translation());
    if (px && px->x() >= 0 && px->y() >= 0 && px->x() < cam->width && px->y() < cam->height) return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sgt;
  const Args args = parse(argc, argv);
  try {
    params::TrackerParameters tracker_params;
    params::applyYamlFile(params::trackerSchema(), tracker_params, args.params);
    params::DetectorParameters detector_params;
    if (!args.detector.empty()) params::applyYamlFile(params::detectorSchema(), detector_params, args.detector_params);
    auto catalog = std::make_shared<ObjectCatalog>(loadObjectCatalog(args.catalog, args.mesh_dir));
    std::optional<Building> building;
    if (args.map == "building") building = makeBuilding();
    auto map = std::make_shared<TriangleMesh>(building ? building->mesh : loadStaticMap(args.map));
    std::optional<sim::Scenario> scenario;
    if (!args.scenario.empty()) scenario = sim::loadScenario(args.scenario);
    sgt::ros::BagFrameReader reader(args.bag);
    reader.setAssemblerOptions(sgt::ros::assemblerOptions(tracker_params.node));  // as the nodelet
    std::unique_ptr<detection::PoseDetector> detector;
    if (!args.detector.empty()) {
      detector = std::make_unique<detection::PoseDetector>(args.detector, *catalog, detector_params.decode,
                                                           detector_params.pnp);
      reader.setReadRgb(true);
    }
    std::size_t frames_without_rgb = 0;
    std::map<std::string, std::pair<std::size_t, std::size_t>> detections_by_class;  // detections, PnP accepted
    std::set<std::string> detected;  // true objects a hypothesis has found (scored from then on)
    PipelineOptions options = tracker_params.pipeline;
    if (args.oracle_localization) options.localize = false;
    if (!args.relations) options.compute_relations = false;
    // The keypoint detector mixes up box corners (a turned box); simulated hypotheses do not, and
    // on nearly symmetric shapes the search can trade their right rotation for a flipped one.
    if (detector) options.search_orientations = true;
    FramePipeline pipeline(catalog, map, options);
    std::vector<relations::Entity> furniture_entities;
    if (!args.furniture.empty()) furniture_entities = relations::loadFurniture(args.furniture);
    else if (building) furniture_entities = {sim::workbenchEntity(*building)};  // the only furniture it describes
    std::set<std::string> furniture;
    for (const relations::Entity& e : furniture_entities) furniture.insert(e.name);
    pipeline.setFurniture(std::move(furniture_entities));
    const PoseScorer score(*catalog);  // ADD-S to each class's surface

    EvaluationReport report;
    ProgressBar progress("evaluate", reader.frameCount());
    std::size_t done = 0, warnings = 0;
    bool first = true;
    reader.forEach([&](sgt::ros::BagFrame& bf) {
      for (const std::string& w : bf.warnings) std::cerr << "\nwarning: " << w << "\n", ++warnings;
      if (first) {  // start from the bag's own map -> odom prior when it has one
        if (const auto T = reader.mapToOdom(bf.frame.stamp)) pipeline.setMapOdom(*T);
        first = false;
      }
      if (args.oracle_localization && bf.truth && bf.truth->T_map_base)
        pipeline.setMapOdom(*bf.truth->T_map_base * bf.frame.T_odom_base.inverse());
      double detect_ms = 0.0;
      if (detector) {  // the detector is the only source of hypotheses
        bf.frame.hypotheses.clear();
        if (bf.rgb) {
          const auto t0 = std::chrono::steady_clock::now();
          // The registered depth image (the frame's pinhole set) gives the detections their distance.
          const RangeMeasurements* depth = nullptr;
          for (const RangeMeasurements& m : bf.frame.measurements)
            if (std::holds_alternative<PinholeModel>(m.model)) depth = &m;
          const auto detections = detector->detect(bf.rgb->rgb, bf.rgb->camera, depth);
          detect_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
          for (const auto& d : detections) {
            auto& [found, accepted] = detections_by_class[d.detection.class_name];
            ++found, accepted += d.pnp.ok();
            if (d.pnp.ok())
              bf.frame.hypotheses.push_back(
                  {d.detection.class_name, bf.rgb->T_base_camera * d.pnp.T_camera_object, d.detection.score});
          }
        } else {
          ++frames_without_rgb;
        }
      }
      PipelineResult r = pipeline.process(bf.frame);
      r.times.detect_ms = detect_ms;
      report.addFrame(r.stamp, r.times);
      if (bf.truth) {
        const sgt::ros::GroundTruth& gt = *bf.truth;
        if (gt.T_map_base)
          report.addLocalization(r.stamp, (r.T_map_base.translation() - gt.T_map_base->translation()).norm(),
                                 angleDeg(r.T_map_base.linear(), gt.T_map_base->linear()));
        // Each true object against the nearest estimate of its class (each estimate used once)
        // within a gate of the object's diameter (at least 10 cm), as CLEAR-MOT matches: a track
        // farther away is no estimate of this object (a miss, and no identity switch). An object is
        // scored from the first frame a hypothesis of its class (simulated, or the detector's with
        // --detector) lies within that gate of it: before, the tracker has nothing to start from
        // (the simulated detector misses the screwdriver at 2.8 m). Later frames without an
        // estimate are misses, hidden or not.
        // hypotheses.*: the nearest hypothesis of each true object in view, scored like a track.
        const Eigen::Isometry3d T_map_base = gt.T_map_base ? *gt.T_map_base : r.T_map_base;
        for (const auto& t : gt.objects) {
          if (!catalog->contains(t.class_name)) continue;
          const PoseHypothesis* nearest = nullptr;
          double nearest_d = std::max(0.1, catalog->get(t.class_name).diameter);  // the gate
          for (const PoseHypothesis& h : bf.frame.hypotheses) {
            const double d = ((T_map_base * h.T_base_object).translation() - t.T_map_object.translation()).norm();
            if (t.class_name == h.class_name && d < nearest_d) nearest_d = d, nearest = &h;
          }
          if (nearest) detected.insert(t.id);
          if (!gt.T_map_base || inView(bf.frame, *gt.T_map_base, t.T_map_object))
            report.addHypothesis(t.id, nearest ? std::optional<PoseErrors>(score(t.class_name, T_map_base * nearest->T_base_object,
                                                                                  t.T_map_object))
                                               : std::nullopt);
        }
        std::vector<char> used(r.objects.size(), 0);
        std::map<std::string, std::string> track_to_object;
        for (const auto& t : gt.objects) {
          if (!catalog->contains(t.class_name)) continue;
          std::size_t best = r.objects.size();
          double best_d = 1e9;
          for (std::size_t k = 0; k < r.objects.size(); ++k) {
            if (r.objects[k].class_name != t.class_name) continue;
            const double d = (r.objects[k].T_map_object.translation() - t.T_map_object.translation()).norm();
            const double gate = std::max(0.1, catalog->get(t.class_name).diameter);
            if (!used[k] && d < best_d && d < gate) best_d = d, best = k;
          }
          if (best < r.objects.size()) used[best] = 1;  // its track, whether scored yet or not
          if (!detected.count(t.id)) continue;           // before its first hypothesis: nothing to track yet
          std::optional<PoseErrors> e;
          std::string track;
          if (best < r.objects.size()) {
            track = r.objects[best].id;
            // Relations are judged between objects in the scene graph (confirmed or lost tracks)
            // estimated within 10 cm: tracking failures are the objects.* figures' business.
            if (r.objects[best].state != TrackState::kTentative && best_d < 0.1) track_to_object[track] = t.id;
            e = score(t.class_name, r.objects[best].T_map_object, t.T_map_object);
          }
          report.addObject(r.stamp, t.id, t.class_name, track, e, !gt.T_map_base || inView(bf.frame, *gt.T_map_base, t.T_map_object));
        }
        for (std::size_t k = 0; k < r.objects.size(); ++k)
          if (!used[k] && r.objects[k].state != TrackState::kTentative)
            report.addFalsePositive(r.stamp, r.objects[k].id, r.objects[k].class_name);
        if (scenario && !scenario->relations.empty())
          report.addRelations(scoreRelations(r.stamp - scenario->start_time, scenario->relations, r.relations,
                                             track_to_object, furniture),
                              scenario->relations.size());
        UnknownLabelCounts counts;
        for (std::size_t s = 0; s < r.presegmentation.size() && s < gt.labels.size(); ++s) {
          const auto& labels = gt.labels[s];
          const auto& p = r.presegmentation[s];
          if (labels.size() != p.label.size()) continue;
          const bool lidar = std::holds_alternative<SpinningLidarModel>(r.measurements[s].model);
          for (std::size_t i = 0; i < labels.size(); ++i) {
            if (p.label[i] == PointLabel::kInvalid) continue;
            const bool truth_unknown = labels[i] == static_cast<std::uint8_t>(sgt::ros::TruthLabel::kDistractor);
            const bool said_unknown = p.label[i] == PointLabel::kUnknown;
            counts.tp += truth_unknown && said_unknown, counts.fp += !truth_unknown && said_unknown;
            counts.fn += truth_unknown && !said_unknown;
            if (lidar) ++counts.lidar_valid, counts.lidar_unknown += said_unknown;
          }
        }
        report.addPresegmentation(counts);
      }
      progress.update(++done);
    });
    progress.finish();
    if (detector) {
      std::cout << "detector: detections (PnP accepted) per class:";
      for (const auto& [c, n] : detections_by_class) std::cout << " " << c << " " << n.first << " (" << n.second << ")";
      std::cout << "\n";
    }
    if (frames_without_rgb > 0)
      std::cerr << "warning: " << frames_without_rgb << " frames had no colour image: no detections for them\n";

    std::filesystem::create_directories(args.output);
    std::ofstream(args.output + "/report.json") << report.json();
    std::ofstream(args.output + "/report.md") << report.markdown();
    std::ofstream(args.output + "/timeseries.csv") << report.timeseriesCsv();
    if (args.plots) {
      const std::string cmd = "/usr/bin/python3 " + std::string(SGT_SOURCE_DIR) + "/scripts/plot_report.py '" +
                              args.output + "'";
      if (std::system(cmd.c_str()) != 0) std::cerr << "warning: plotting failed (" << cmd << ")\n";
    }
    std::cout << report.markdown() << "\n"
              << report.frames() << " frames" << (reader.hasGroundTruth() ? "" : " (the bag has no ground truth)")
              << ", " << warnings << " warnings. Report: " << args.output << "/report.json, report.md; plots: "
              << args.output << "/*.png\n";
  } catch (const std::exception& e) {
    std::cerr << "evaluate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
