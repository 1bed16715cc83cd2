// Evaluates a keypoint model on held-out frames (a data set written by render_dataset, or by
// sequence_to_dataset from a real recording): detection precision / recall (IoU >= 0.5, same
// class), keypoint error of matched detections (px, over keypoints labelled inside the image), PnP
// initial pose error (translation mm, rotation degrees symmetry-aware, ADD-S mm; the rotation also
// up to a half turn of the box, what cuboid labels can tell, and up to the turns of its box that
// look alike, what shape labels can tell: detection/label_kind.hpp), the share of labelled objects
// whose PnP pose is within 3 cm and 15 degrees (also up to those turns), and inference time per
// frame (median, ms). A set with
// depth images (depth/) gives the detector the depth, as the nodes do. The model's
// own per-class score_thresholds are ignored here: per class it reports precision / recall at score
// thresholds 0.35 ... 0.8 and suggests a threshold, the one with the best F-beta (F1 unless
// --threshold-beta; 2 weighs recall twice, for a tracker that checks each hypothesis against the
// depth anyway) where the detector is reliable for the class there (precision >= 0.7); a class it
// is not reliable for keeps the global threshold (raising it would lose true detections the
// tracker needs without making the rest trustworthy). --write-thresholds puts the suggestions
// into the model's metadata YAML.
//   rosrun scene_graph_tracker evaluate_detector --dataset DIR --model MODEL.yaml --output OUT
//       [--catalog objects.yaml] [--limit N] [--debug-images K] [--write-thresholds]
//       [--threshold-beta B]
// Writes OUT/report.json and OUT/debug_*.png (the first K frames with drawn detections).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "command_line.hpp"
#include "scene_graph_tracker/detection/debug_drawing.hpp"
#include "scene_graph_tracker/detection/keypoint_labels.hpp"
#include "scene_graph_tracker/detection/label_kind.hpp"
#include "scene_graph_tracker/detection/pose_detector.hpp"
#include "scene_graph_tracker/evaluation/pose_metrics.hpp"
#include "scene_graph_tracker/util/progress_bar.hpp"

namespace fs = std::filesystem;
using namespace sgt;

namespace {

struct Args {
  std::string dataset, model, output, mesh_dir,
      catalog = "package://scene_graph_tracker/config/objects.yaml";
  std::size_t limit = 0;
  int debug_images = 8;
  bool write_thresholds = false;
  double threshold_beta = 1.0;
};

Args parse(int argc, char** argv) {
  const sgt::cli::Flags flags(
      "evaluate_detector",
      "--dataset DIR --model MODEL.yaml --output OUT [--catalog FILE] [--mesh-dir D] "
      "[--limit N] [--debug-images K] "
      "[--write-thresholds] [--threshold-beta B]");
  Args a;
  flags.parse(argc, argv, [&](const std::string& k, const std::function<std::string()>& value) {
    if (k == "--dataset")
      a.dataset = value();
    else if (k == "--model")
      a.model = value();
    else if (k == "--output")
      a.output = value();
    else if (k == "--catalog")
      a.catalog = value();
    else if (k == "--mesh-dir")
      a.mesh_dir = value();
    else if (k == "--limit")
      a.limit = std::stoul(value());
    else if (k == "--debug-images")
      a.debug_images = std::stoi(value());
    else if (k == "--write-thresholds")
      a.write_thresholds = true;
    else if (k == "--threshold-beta")
      a.threshold_beta = std::stod(value());
    else
      return false;
    return true;
  });
  if (a.dataset.empty() || a.model.empty() || a.output.empty())
    flags.fail("--dataset, --model and --output are required");
  if (!(a.threshold_beta > 0.0)) flags.fail("--threshold-beta must be positive");
  return a;
}

struct TruthObject {
  std::string class_name;
  Eigen::Isometry3d T_camera_object;
  Eigen::Vector2d box_min, box_max;  // pixel-centre coordinates
  std::vector<std::optional<Eigen::Vector2d>> keypoints;
};

Eigen::Isometry3d matrix(const YAML::Node& m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = m[r][c].as<double>();
  return T;
}

// poses/NAME.json and labels/NAME.txt list the same objects in the same order.
std::vector<TruthObject> readTruth(const fs::path& dir, const std::string& name,
                                   PinholeModel& camera) {
  const YAML::Node j = YAML::LoadFile((dir / "poses" / (name + ".json")).string());
  camera.width = j["width"].as<int>(), camera.height = j["height"].as<int>();
  camera.fx = j["K"][0].as<double>(), camera.cx = j["K"][2].as<double>();
  camera.fy = j["K"][4].as<double>(), camera.cy = j["K"][5].as<double>();
  std::vector<TruthObject> out;
  for (const auto& o : j["objects"])
    out.push_back({o["class"].as<std::string>(), matrix(o["T_camera_object"]), {}, {}, {}});
  std::ifstream labels(dir / "labels" / (name + ".txt"));
  const double W = camera.width, H = camera.height;
  for (TruthObject& t : out) {
    double cls, cx, cy, w, h;
    if (!(labels >> cls >> cx >> cy >> w >> h))
      throw std::runtime_error("labels/" + name + ".txt: fewer lines than objects");
    t.box_min = Eigen::Vector2d((cx - w / 2) * W - 0.5, (cy - h / 2) * H - 0.5);
    t.box_max = Eigen::Vector2d((cx + w / 2) * W - 0.5, (cy + h / 2) * H - 0.5);
    for (int k = 0; k < detection::kCuboidKeypoints; ++k) {
      double x, y, v;
      labels >> x >> y >> v;
      t.keypoints.push_back(
          v > 0 ? std::optional<Eigen::Vector2d>(Eigen::Vector2d(x * W - 0.5, y * H - 0.5))
                : std::nullopt);
    }
  }
  return out;
}

// depth/NAME.png (16-bit mm) as the camera's range measurements, or null when the set has none.
std::unique_ptr<RangeMeasurements> readDepth(const fs::path& dir, const std::string& name,
                                             const PinholeModel& camera) {
  const fs::path path = dir / "depth" / (name + ".png");
  if (!fs::exists(path)) return nullptr;
  const cv::Mat mm = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (mm.type() != CV_16UC1 || mm.cols != camera.width || mm.rows != camera.height)
    throw std::runtime_error(path.string() + ": not a 16-bit depth image of the camera's size");
  std::vector<float> m;
  m.reserve(mm.total());
  for (int r = 0; r < mm.rows; ++r)
    for (int c = 0; c < mm.cols; ++c) {
      const std::uint16_t v = mm.at<std::uint16_t>(r, c);
      m.push_back(v ? v * 0.001f : NAN);
    }
  return std::make_unique<RangeMeasurements>(fromDepthImage(
      camera, std::make_shared<SensorRays>(makeRays(camera)), m, Eigen::Isometry3d::Identity()));
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

struct ClassStats {
  std::size_t truths = 0, detections = 0, matched = 0, pnp_ok = 0;
  std::size_t pnp_close = 0;  // PnP within kCloseTranslation and kCloseRotationDeg of the truth
  std::size_t pnp_close_shape = 0;  // the same up to the turns of its box that look alike
  std::vector<double> kp_px, t_mm, r_deg, adds_mm, r_box_deg, r_shape_deg;
  std::vector<std::pair<float, bool>>
      scores;  // each detection's score and whether it matched a truth
};

// Precision and recall of the detections scoring at least t. Matching is greedy by score, so a
// higher threshold keeps exactly the matches it had.
struct ScorePoint {
  float threshold;
  double precision, recall;
  double f(double beta) const {
    const double b2 = beta * beta;
    return precision + recall > 0 ? (1 + b2) * precision * recall / (b2 * precision + recall) : 0.0;
  }
};
std::vector<ScorePoint> scoreCurve(const ClassStats& s) {
  std::vector<ScorePoint> out;
  for (int i = 0; i <= 9; ++i) {
    const float t = 0.35f + 0.05f * i;
    std::size_t kept = 0, matched = 0;
    for (const auto& [score, m] : s.scores)
      if (score >= t) ++kept, matched += m;
    const double p = kept ? static_cast<double>(matched) / kept : 0.0;
    const double r = s.truths ? static_cast<double>(matched) / s.truths : 0.0;
    out.push_back({t, p, r});
  }
  return out;
}
const ScorePoint& bestF(const std::vector<ScorePoint>& curve, double beta) {
  const ScorePoint* best = &curve.front();
  for (const ScorePoint& q : curve)
    if (q.f(beta) > best->f(beta) + 1e-9) best = &q;
  return *best;
}
constexpr double kReliablePrecision = 0.7;
// A PnP pose this close to the truth is a good start for the tracker (issue 24's goal).
constexpr double kCloseTranslation = 0.03, kCloseRotationDeg = 15.0;

// Replaces the metadata's score_thresholds line (and its comment) with `line`.
void writeThresholds(const std::string& yaml_path, const std::string& line,
                     const std::string& rule) {
  std::ifstream in(yaml_path);
  std::ostringstream kept;
  for (std::string l; std::getline(in, l);)
    if (l.rfind("score_thresholds:", 0) != 0 && l.rfind("# score_thresholds", 0) != 0)
      kept << l << "\n";
  std::ofstream(yaml_path)
      << kept.str()
      << "# score_thresholds: per class, suggested by evaluate_detector on held-out renders (best "
      << rule << " where precision >= " << kReliablePrecision << ")\n"
      << line << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse(argc, argv);
  try {
    const ObjectCatalog catalog = loadObjectCatalog(args.catalog, args.mesh_dir);
    detection::PoseDetector detector(args.model, catalog);
    detector.keypoints().clearScoreThresholds();
    const PoseScorer score(catalog);                 // ADD-S to each class's surface
    std::map<std::string, Symmetry> shape_symmetry;  // what shape labels cannot tell apart
    for (const auto& name : catalog.listed())
      shape_symmetry[name] =
          detection::labelSymmetry(catalog.get(name), detection::LabelKind::kShape);
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(fs::path(args.dataset) / "images"))
      if (e.path().extension() == ".png") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    if (args.limit && names.size() > args.limit) names.resize(args.limit);
    if (names.empty()) throw std::runtime_error("no images in " + args.dataset + "/images");
    fs::create_directories(args.output);

    std::map<std::string, ClassStats> per;
    std::size_t frames_with_depth = 0;
    std::vector<double> infer_ms;
    ProgressBar progress("evaluate_detector", names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
      PinholeModel camera;
      const auto truth = readTruth(args.dataset, names[i], camera);
      cv::Mat bgr = cv::imread((fs::path(args.dataset) / "images" / (names[i] + ".png")).string(),
                               cv::IMREAD_COLOR);
      if (bgr.empty()) throw std::runtime_error("cannot read image " + names[i]);
      cv::Mat rgb;
      cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
      const auto t0 = std::chrono::steady_clock::now();
      const auto depth = readDepth(args.dataset, names[i], camera);
      frames_with_depth += depth != nullptr;
      const auto dets = detector.detect(rgb, camera, depth.get());
      infer_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      for (const auto& t : truth) ++per[t.class_name].truths;
      // Greedy matching by score: each detection to the unmatched truth of its class with the best
      // IoU >= 0.5.
      std::vector<char> used(truth.size(), 0);
      for (const auto& d : dets) {
        ClassStats& s = per[d.detection.class_name];
        ++s.detections;
        std::size_t best = truth.size();
        double best_iou = 0.5;
        for (std::size_t k = 0; k < truth.size(); ++k) {
          if (used[k] || truth[k].class_name != d.detection.class_name) continue;
          detection::Detection tb;
          tb.box_min = truth[k].box_min, tb.box_max = truth[k].box_max;
          const double iou = detection::iou(d.detection, tb);
          if (iou >= best_iou) best_iou = iou, best = k;
        }
        s.scores.emplace_back(d.detection.score, best != truth.size());
        if (best == truth.size()) continue;
        used[best] = 1;
        ++s.matched;
        for (std::size_t k = 0;
             k < truth[best].keypoints.size() && k < d.detection.keypoints.size(); ++k)
          if (truth[best].keypoints[k])
            s.kp_px.push_back((d.detection.keypoints[k].px - *truth[best].keypoints[k]).norm());
        if (d.pnp.ok() && catalog.contains(d.detection.class_name)) {
          ++s.pnp_ok;
          const PoseErrors e =
              score(d.detection.class_name, d.pnp.T_camera_object, truth[best].T_camera_object);
          s.t_mm.push_back(e.translation * 1000), s.r_deg.push_back(e.rotation_deg),
              s.adds_mm.push_back(e.add_s * 1000);
          s.pnp_close += e.translation <= kCloseTranslation && e.rotation_deg <= kCloseRotationDeg;
          double r_box =
              e.rotation_deg;  // up to a half turn of the box (all cuboid labels can tell)
          for (const Eigen::Isometry3d& B : detection::boxHalfTurns())
            r_box = std::min(r_box,
                             symmetricRotationErrorDeg(catalog.get(d.detection.class_name).symmetry,
                                                       (d.pnp.T_camera_object * B).linear(),
                                                       truth[best].T_camera_object.linear()));
          s.r_box_deg.push_back(r_box);
          const auto shape = shape_symmetry.find(d.detection.class_name);
          const double r_shape = symmetricRotationErrorDeg(
              shape->second, d.pnp.T_camera_object.linear(), truth[best].T_camera_object.linear());
          s.r_shape_deg.push_back(r_shape);
          s.pnp_close_shape += e.translation <= kCloseTranslation && r_shape <= kCloseRotationDeg;
        }
      }
      if (static_cast<int>(i) < args.debug_images) {
        detection::drawDetections(rgb, dets);
        cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
        cv::imwrite((fs::path(args.output) / ("debug_" + names[i] + ".png")).string(), bgr);
      }
      progress.update(i + 1);
    }
    progress.finish();

    ClassStats all;
    for (const auto& [c, s] : per) {
      all.truths += s.truths, all.detections += s.detections, all.matched += s.matched,
          all.pnp_ok += s.pnp_ok, all.pnp_close += s.pnp_close,
          all.pnp_close_shape += s.pnp_close_shape;
      for (auto v : {&ClassStats::kp_px, &ClassStats::t_mm, &ClassStats::r_deg,
                     &ClassStats::adds_mm, &ClassStats::r_box_deg, &ClassStats::r_shape_deg})
        (all.*v).insert((all.*v).end(), (s.*v).begin(), (s.*v).end());
    }
    const auto ratio = [](std::size_t a, std::size_t b) {
      return b ? static_cast<double>(a) / b : NAN;
    };
    const auto num = [](double x) {
      std::ostringstream o;
      if (std::isfinite(x))
        o << std::setprecision(4) << x;
      else
        o << "null";
      return o.str();
    };
    const auto stats_json = [&](const ClassStats& s, const std::string& indent) {
      std::ostringstream o;
      o << indent << "\"truths\": " << s.truths << ", \"detections\": " << s.detections
        << ", \"matched\": " << s.matched << ",\n"
        << indent << "\"precision\": " << num(ratio(s.matched, s.detections))
        << ", \"recall\": " << num(ratio(s.matched, s.truths)) << ",\n"
        << indent << "\"keypoint_error_px_mean\": " << num(mean(s.kp_px))
        << ", \"keypoint_error_px_median\": " << num(median(s.kp_px)) << ",\n"
        << indent << "\"pnp_ok\": " << s.pnp_ok
        << ", \"pnp_translation_error_mm_median\": " << num(median(s.t_mm))
        << ", \"pnp_rotation_error_deg_median\": " << num(median(s.r_deg))
        << ", \"pnp_add_s_mm_median\": " << num(median(s.adds_mm)) << ",\n"
        << indent
        << "\"pnp_rotation_error_up_to_box_turns_deg_median\": " << num(median(s.r_box_deg))
        << ",\n"
        << indent
        << "\"pnp_rotation_error_up_to_shape_turns_deg_median\": " << num(median(s.r_shape_deg))
        << ",\n"
        << indent << "\"pnp_within_3cm_15deg_rate\": " << num(ratio(s.pnp_close, s.truths))
        << ", \"pnp_within_3cm_15deg_up_to_shape_turns_rate\": "
        << num(ratio(s.pnp_close_shape, s.truths));
      return o.str();
    };
    std::map<std::string, std::vector<ScorePoint>> curves;
    for (const auto& [c, s] : per) curves[c] = scoreCurve(s);
    std::ostringstream j;
    j << "{\n  \"frames\": " << names.size() << ",\n  \"model\": \"" << args.model << "\",\n"
      << "  \"frames_with_depth\": " << frames_with_depth << ",\n"
      << "  \"inference_ms_median\": " << num(median(infer_ms))
      << ",\n  \"threshold_beta\": " << num(args.threshold_beta) << ",\n  \"all\": {\n"
      << stats_json(all, "    ") << "\n  },\n  \"per_class\": {";
    bool first = true;
    for (const auto& [c, s] : per) {
      const auto& curve = curves.at(c);
      const ScorePoint& best = bestF(curve, args.threshold_beta);
      j << (first ? "\n" : ",\n") << "    \"" << c << "\": {\n"
        << stats_json(s, "      ")
        << ",\n      \"best_f1_score_threshold\": " << bestF(curve, 1.0).threshold
        << ", \"suggested_score_threshold\": "
        << (best.precision >= kReliablePrecision ? num(best.threshold) : "null")
        << ",\n      \"score_curve\": [";
      for (std::size_t i = 0; i < curve.size(); ++i)
        j << (i ? ", " : "") << "{\"threshold\": " << curve[i].threshold
          << ", \"precision\": " << num(curve[i].precision)
          << ", \"recall\": " << num(curve[i].recall) << "}";
      j << "]\n    }";
      first = false;
    }
    j << "\n  }\n}\n";
    std::ofstream(fs::path(args.output) / "report.json") << j.str();

    std::cout << "\n| class | truths | precision | recall | keypoint px (median) | PnP ok | PnP t "
                 "mm (median) | R deg | ADD-S mm |\n"
              << "|---|---|---|---|---|---|---|---|---|\n";
    const auto row = [&](const std::string& name, const ClassStats& s) {
      std::cout << "| " << name << " | " << s.truths << " | " << num(ratio(s.matched, s.detections))
                << " | " << num(ratio(s.matched, s.truths)) << " | " << num(median(s.kp_px))
                << " | " << s.pnp_ok << " | " << num(median(s.t_mm)) << " | "
                << num(median(s.r_deg)) << " | " << num(median(s.adds_mm)) << " |\n";
    };
    for (const auto& [c, s] : per) row(c, s);
    row("**all**", all);
    const std::string rule = args.threshold_beta == 1.0 ? "F1" : "F" + num(args.threshold_beta);
    std::cout << "\nscore threshold with the best " << rule
              << " per class (precision / recall there):";
    std::ostringstream suggested;
    const char* sep = "";
    for (const auto& [c, curve] : curves) {
      const ScorePoint& best = bestF(curve, args.threshold_beta);
      std::cout << " " << c << " " << best.threshold << " (" << num(best.precision) << " / "
                << num(best.recall) << ")";
      if (best.precision >= kReliablePrecision)
        suggested << sep << c << ": " << best.threshold, sep = ", ";
    }
    const std::string line = "score_thresholds: {" + suggested.str() + "}";
    std::cout << "\nsuggested (best " << rule << " where precision >= " << kReliablePrecision
              << "; others keep the global): " << line << "\n";
    if (args.write_thresholds) {
      writeThresholds(args.model, line, rule);
      std::cout << "written into " << args.model << "\n";
    }
    std::cout << "\ninference (detector incl. letterbox + decoding + PnP) median "
              << num(median(infer_ms)) << " ms per frame. Report: " << args.output
              << "/report.json\n";
  } catch (const std::exception& e) {
    std::cerr << "evaluate_detector: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
