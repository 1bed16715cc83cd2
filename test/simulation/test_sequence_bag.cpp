// A recorded RGB-D sequence folder (evaluation/rgbd_sequence.hpp) into a bag (sequence_to_bag's
// writer) and back through the bag reader, and the depth residual of poses on it
// (evaluation/surface_fit.hpp). The folder is made here: a 10 cm cube 0.5 m in front of a camera
// that moves sideways, its depth rendered by ray casting. The real sequence, when present, loads.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/evaluation/keypoint_dataset.hpp"
#include "scene_graph_tracker/evaluation/rgbd_sequence.hpp"
#include "scene_graph_tracker/evaluation/surface_fit.hpp"
#include "scene_graph_tracker/geometry/mesh_io.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/ros/bag_frames.hpp"
#include "scene_graph_tracker/simulation/sequence_bag.hpp"
#include "support.hpp"

namespace sgt {
namespace {

PinholeModel smallCamera() {
  PinholeModel cam;
  cam.width = 80, cam.height = 60, cam.fx = cam.fy = 70.0, cam.cx = 39.5, cam.cy = 29.5;
  return cam;
}

nlohmann::json rows(const Eigen::Isometry3d& T) {
  nlohmann::json j = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) j.push_back({T(r, 0), T(r, 1), T(r, 2), T(r, 3)});
  return j;
}

// Depth (mm) of `mesh` at T_camera_object seen by `cam`.
cv::Mat renderDepth(const PinholeModel& cam, std::shared_ptr<const TriangleMesh> mesh,
                    const Eigen::Isometry3d& T_camera_object) {
  RaycastScene scene;
  scene.addInstance(1, scene.addMesh(mesh), T_camera_object);
  scene.commit();
  const SensorRays rays = makeRays(cam);
  RayHits hits;
  scene.cast(rays, Eigen::Isometry3d::Identity(), hits);
  cv::Mat mm(cam.height, cam.width, CV_16UC1, cv::Scalar(0));
  for (std::size_t i = 0; i < hits.size(); ++i)
    if (hits.hit(i))
      mm.at<std::uint16_t>(static_cast<int>(i) / cam.width, static_cast<int>(i) % cam.width) =
          static_cast<std::uint16_t>(std::lround(hits.range[i] * rays.directions[i].z() * 1000));
  return mm;
}

// What a mesh alone reaches on a depth image: from 17 mm and 3 deg off, the fit comes back onto a
// cube seen on three faces, in the world frame the depth image is in (2 m from the origin).
TEST(SurfaceFitter, AMeshFittedAloneComesBackOntoItsSurface) {
  PinholeModel cam;
  cam.width = 160, cam.height = 120, cam.fx = cam.fy = 150.0, cam.cx = 79.5, cam.cy = 59.5;
  auto cube = std::make_shared<TriangleMesh>(makeBox(Eigen::Vector3f(0.1f, 0.1f, 0.1f), 4));
  const std::string mesh = test::tempDir() + "/fit_alone_cube.ply";
  savePly(*cube, mesh);
  const Eigen::Isometry3d T_camera_object(
      Eigen::Translation3d(0.02, -0.01, 0.5) *
      Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 1, 0).normalized()));
  const cv::Mat mm = renderDepth(cam, cube, T_camera_object);
  std::vector<float> depth(mm.total());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    const std::uint16_t d = mm.at<std::uint16_t>(static_cast<int>(i));
    depth[i] = d > 0 ? d * 0.001f : NAN;
  }
  const Eigen::Isometry3d T_world_camera(Eigen::Translation3d(2, 0, 1) *
                                         Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const RangeMeasurements m =
      fromDepthImage(cam, std::make_shared<const SensorRays>(makeRays(cam)), depth, T_world_camera);
  SurfaceFitter fitter(std::make_shared<const ObjectCatalog>(loadObjectCatalog(
      test::writeFile("fit_alone.yaml", "objects:\n  cube:\n    mesh: " + mesh + "\n"))));
  PosedObject start{"a", "cube",
                    T_camera_object * Eigen::Translation3d(0.01, 0.01, 0.01) *
                        Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d::UnitY())};
  EXPECT_GT(fitter.fit(m, {start})[0].median_residual_m, 0.002);
  const SurfaceFit fitted = fitter.fitAlone(m, start);
  EXPECT_LT(fitted.median_residual_m, 0.0006);
  EXPECT_LT((start.T_camera_object.translation() - T_camera_object.translation()).norm(), 0.002);
}

class SequenceBag : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir() + "/sequence_" + std::to_string(++count_);
    for (const char* d : {"rgb", "depth", "models"})
      std::filesystem::create_directories(dir_ + "/" + d);
    auto cube = std::make_shared<TriangleMesh>(makeBox(Eigen::Vector3f(0.1f, 0.1f, 0.1f), 4));
    savePly(*cube, dir_ + "/models/cube.ply");
    const PinholeModel cam = smallCamera();
    std::ofstream(dir_ + "/camera.json")
        << nlohmann::json{{"width", cam.width},    {"height", cam.height}, {"fx", cam.fx},
                          {"fy", cam.fy},          {"cx", cam.cx},         {"cy", cam.cy},
                          {"depth_unit_m", 0.001}, {"distortion", "none"}};
    T_map_object_ = test::poseXyzYaw({1.0, 0.2, 0.3}, 0.4);
    nlohmann::json frames = nlohmann::json::array();
    for (int k = 0; k < 2; ++k) {
      Eigen::Isometry3d T_map_camera = T_map_object_ * test::poseXyzYaw({0.02 * k, 0.0, -0.5});
      T_map_cameras_.push_back(T_map_camera);
      const Eigen::Isometry3d T_camera_object = T_map_camera.inverse() * T_map_object_;
      char name[32];
      std::snprintf(name, sizeof name, "%06d.png", k);
      cv::imwrite(dir_ + "/depth/" + name, renderDepth(cam, cube, T_camera_object));
      cv::imwrite(dir_ + "/rgb/" + name,
                  cv::Mat(cam.height, cam.width, CV_8UC3, cv::Scalar(90, 120, 150)));
      frames.push_back({{"frame", k},
                        {"T_map_camera", rows(T_map_camera)},
                        {"objects", {{"cube", rows(T_camera_object)}}}});
    }
    std::ofstream(dir_ + "/poses.json")
        << nlohmann::json{{"frames", frames}, {"T_map_object", {{"cube", rows(T_map_object_)}}}};
  }

  ros::BagTopics cameraOnlyTopics() const {
    ros::BagTopics topics;
    topics.odom_frame = "map";
    topics.base_frame = "camera_color_optical_frame";
    return topics;
  }

  std::shared_ptr<ObjectCatalog> catalog() const {
    const std::string yaml =
        test::writeFile("sequence_catalog_" + std::to_string(count_) + ".yaml",
                        "objects:\n  cube:\n    mesh: " + dir_ + "/models/cube.ply\n");
    return std::make_shared<ObjectCatalog>(loadObjectCatalog(yaml));
  }

  static inline int count_ = 0;
  std::string dir_;
  Eigen::Isometry3d T_map_object_;
  std::vector<Eigen::Isometry3d> T_map_cameras_;
};

TEST_F(SequenceBag, TheFolderLoadsWithItsPosesAndImages) {
  const RgbdSequence s = loadRgbdSequence(dir_);
  ASSERT_EQ(s.frames.size(), 2u);
  EXPECT_EQ(s.objectNames(), std::vector<std::string>{"cube"});
  EXPECT_TRUE(s.T_map_object.at("cube").isApprox(T_map_object_, 1e-9));
  EXPECT_TRUE(s.frames[1].T_map_camera.isApprox(T_map_cameras_[1], 1e-9));
  const std::vector<float> depth = loadSequenceDepth(s, s.frames[0]);
  const std::size_t centre = 30 * 80 + 40;
  EXPECT_NEAR(depth[centre], 0.45, 0.002);  // the cube's front face, 5 cm before its centre
  EXPECT_TRUE(std::isnan(depth[0]));        // no return: NaN
  EXPECT_EQ(loadSequenceRgb(s, s.frames[0]).type(), CV_8UC3);
}

TEST_F(SequenceBag, BrokenFoldersAreRefusedWithTheirReason) {
  std::filesystem::remove(dir_ + "/depth/000001.png");
  try {
    loadRgbdSequence(dir_);
    FAIL() << "a missing depth image was accepted";
  } catch (const SequenceError& e) {
    EXPECT_NE(std::string(e.what()).find("000001.png does not exist"), std::string::npos)
        << e.what();
  }
  std::ofstream(dir_ + "/poses.json")
      << R"({"frames": [{"frame": 0, "T_map_camera": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  EXPECT_THROW(loadRgbdSequence(dir_), SequenceError);  // a scaled "rotation"
  std::filesystem::remove(dir_ + "/camera.json");
  EXPECT_THROW(loadRgbdSequence(dir_), SequenceError);
}

TEST_F(SequenceBag, TheBagReplaysAsACameraOnlyRobotWithExternalLocalization) {
  const RgbdSequence s = loadRgbdSequence(dir_);
  ros::SequenceBagOptions options;
  options.sigma_t = 0.0, options.sigma_r_deg = 0.0;
  const std::string bag = test::tempDir() + "/sequence_" + std::to_string(count_) + ".bag";
  const auto summary = ros::writeSequenceBag(s, bag, options);
  EXPECT_EQ(summary.frames, 2u);
  EXPECT_EQ(summary.hypotheses, 2u);
  ros::BagFrameReader reader(bag, cameraOnlyTopics());
  EXPECT_TRUE(reader.hasGroundTruth());
  ASSERT_TRUE(reader.mapToOdom(options.start_time));
  EXPECT_TRUE(reader.mapToOdom(options.start_time)->isApprox(Eigen::Isometry3d::Identity()));
  std::size_t k = 0;
  SurfaceFitter fitter(catalog());
  reader.forEach([&](ros::BagFrame& bf) {
    ASSERT_LT(k, 2u);
    EXPECT_TRUE(bf.warnings.empty());
    EXPECT_TRUE(bf.frame.T_odom_base.isApprox(T_map_cameras_[k], 1e-6));
    ASSERT_EQ(bf.frame.measurements.size(), 1u);  // the depth image only
    ASSERT_EQ(bf.frame.hypotheses.size(), 1u);
    const Eigen::Isometry3d T_camera_object = T_map_cameras_[k].inverse() * T_map_object_;
    EXPECT_TRUE(bf.frame.hypotheses[0].T_base_object.isApprox(T_camera_object, 1e-6));
    ASSERT_TRUE(bf.truth);
    ASSERT_EQ(bf.truth->objects.size(), 1u);
    EXPECT_TRUE(bf.truth->objects[0].T_map_object.isApprox(T_map_object_, 1e-6));
    // The true pose explains the depth to its millimetre rounding; 1 cm farther, by 1 cm.
    const RangeMeasurements& depth = bf.frame.measurements[0];
    Eigen::Isometry3d farther = T_camera_object;
    farther.translation().z() += 0.01;
    std::vector<int> owner;
    const auto fits =
        fitter.fit(depth, {{"a", "cube", T_camera_object}, {"b", "cube", farther}}, &owner);
    EXPECT_GT(fits[0].visible_pixels, 100u);
    EXPECT_LT(fits[0].median_residual_m, 0.0006);
    const auto alone = fitter.fit(depth, {{"b", "cube", farther}});
    EXPECT_NEAR(alone[0].median_residual_m, 0.01, 0.001);
    // Fitted alone, the mesh keeps its pose: one face seen is a degenerate fit.
    PosedObject refitted{"b", "cube", farther};
    EXPECT_NEAR(fitter.fitAlone(depth, refitted).median_residual_m, 0.01, 0.001);
    EXPECT_TRUE(refitted.T_camera_object.isApprox(farther, 1e-9));
    EXPECT_EQ(owner[30 * 80 + 40], 0);  // the nearer one hides the farther one
    EXPECT_EQ(owner[0], -1);
    ++k;
  });
  EXPECT_EQ(k, 2u);
}

TEST_F(SequenceBag, CompressedImagesReplayLikeRawOnes) {
  const RgbdSequence s = loadRgbdSequence(dir_);
  ros::SequenceBagOptions options;
  const std::string raw = test::tempDir() + "/raw_" + std::to_string(count_) + ".bag";
  ros::writeSequenceBag(s, raw, options);
  options.compressed = true;
  const std::string compressed = test::tempDir() + "/compressed_" + std::to_string(count_) + ".bag";
  ros::writeSequenceBag(s, compressed, options);
  ros::BagTopics topics = cameraOnlyTopics();
  topics.depth += "/compressedDepth", topics.rgb += "/compressed";
  std::vector<std::vector<float>> raw_ranges, compressed_ranges;
  std::vector<cv::Mat> colours;
  ros::BagFrameReader(raw, cameraOnlyTopics()).forEach([&](ros::BagFrame& bf) {
    raw_ranges.push_back(bf.frame.measurements.at(0).range);
  });
  ros::BagFrameReader reader(compressed, topics);
  reader.setReadRgb(true);
  reader.forEach([&](ros::BagFrame& bf) {
    EXPECT_TRUE(bf.warnings.empty());
    compressed_ranges.push_back(bf.frame.measurements.at(0).range);
    ASSERT_TRUE(bf.rgb);
    colours.push_back(bf.rgb->rgb);
  });
  ASSERT_EQ(compressed_ranges.size(), 2u);
  ASSERT_EQ(raw_ranges.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)  // PNG is lossless: the same millimetres, NaN where none
    for (std::size_t i = 0; i < raw_ranges[k].size(); ++i)
      ASSERT_TRUE(raw_ranges[k][i] == compressed_ranges[k][i] ||
                  (std::isnan(raw_ranges[k][i]) && std::isnan(compressed_ranges[k][i])))
          << "pixel " << i;
  const cv::Vec3b centre = colours[0].at<cv::Vec3b>(30, 40);  // JPEG: close to rgb (150, 120, 90)
  EXPECT_NEAR(centre[0], 150, 3);
  EXPECT_NEAR(centre[2], 90, 3);
}

TEST_F(SequenceBag, HypothesesCarryTheSimulatedDetectorsNoiseAndSeededMisses) {
  const RgbdSequence s = loadRgbdSequence(dir_);
  ros::SequenceBagOptions options;
  options.sigma_t = 0.01, options.sigma_r_deg = 2.0, options.miss_probability = 0.5,
  options.seed = 7;
  const std::string bag = test::tempDir() + "/noisy_" + std::to_string(count_) + ".bag";
  ros::writeSequenceBag(s, bag, options);
  const std::string again = test::tempDir() + "/noisy_again_" + std::to_string(count_) + ".bag";
  ros::writeSequenceBag(s, again, options);
  std::vector<Eigen::Isometry3d> first, second;
  ros::BagFrameReader(bag, cameraOnlyTopics()).forEach([&](ros::BagFrame& bf) {
    for (const auto& h : bf.frame.hypotheses) first.push_back(h.T_base_object);
  });
  ros::BagFrameReader(again, cameraOnlyTopics()).forEach([&](ros::BagFrame& bf) {
    for (const auto& h : bf.frame.hypotheses) second.push_back(h.T_base_object);
  });
  ASSERT_EQ(first.size(), second.size());  // the same seed, the same draws
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_TRUE(first[i].isApprox(second[i]));
    const Eigen::Isometry3d truth = T_map_cameras_[0].inverse() * T_map_object_;
    EXPECT_LT((first[i].translation() - truth.translation()).norm(), 0.1);
  }
}

// sequence_to_dataset's labels: the box and pixel count are the cube's depth pixels, the centre
// keypoint is the projection of its given position, and the written line says so.
TEST_F(SequenceBag, FramesAreLabelledFromTheirGivenPoses) {
  const RgbdSequence s = loadRgbdSequence(dir_);
  const auto cat = catalog();
  SequenceLabeller labeller(*cat, s, detection::LabelKind::kObject, 10);
  const auto& f = s.frames.front();
  const std::vector<DatasetObject> objects = labeller.label(f);
  ASSERT_EQ(objects.size(), 1u);
  const DatasetObject& o = objects[0];
  const cv::Mat depth = cv::imread(f.depth_path, cv::IMREAD_UNCHANGED);
  cv::Mat mask = depth > 0;
  const cv::Rect box = cv::boundingRect(mask);
  EXPECT_EQ(o.visible_pixels, cv::countNonZero(mask));
  EXPECT_EQ(o.x0, box.x);
  EXPECT_EQ(o.y0, box.y);
  EXPECT_EQ(o.x1, box.x + box.width - 1);
  EXPECT_EQ(o.y1, box.y + box.height - 1);
  EXPECT_EQ(o.class_name, "cube");
  EXPECT_TRUE(o.T_camera_object.isApprox(f.T_camera_object.at("cube"), 1e-9));

  const std::string out = test::tempDir() + "/labels_" + std::to_string(count_);
  std::filesystem::create_directories(out + "/labels");
  std::filesystem::create_directories(out + "/poses");
  writeDatasetLabels(out, 0, "real", s.camera, objects);
  std::ifstream txt(out + "/labels/000000.txt");
  std::vector<double> v{std::istream_iterator<double>(txt), std::istream_iterator<double>()};
  ASSERT_EQ(v.size(), 5u + 27u);
  EXPECT_EQ(v[0], 0.0);
  const Eigen::Vector3d c = o.T_camera_object.translation();
  const double u = s.camera.fx * c.x() / c.z() + s.camera.cx,
               w = s.camera.fy * c.y() / c.z() + s.camera.cy;
  EXPECT_NEAR(v[5 + 3 * 8] * s.camera.width - 0.5, u, 1e-3);  // keypoint 8: the centre
  EXPECT_NEAR(v[5 + 3 * 8 + 1] * s.camera.height - 0.5, w, 1e-3);
  EXPECT_EQ(v[5 + 3 * 8 + 2], 2.0);

  const ObjectCatalog other = loadObjectCatalog(test::writeFile(
      "other_catalog.yaml", "objects:\n  dragon:\n    mesh: " + dir_ + "/models/cube.ply\n"));
  EXPECT_THROW(SequenceLabeller(other, s, detection::LabelKind::kObject), std::runtime_error);
}

TEST(RealSequence, TheRealSensorSequenceLoadsWhenPresent) {
  const std::string dir = std::string(SGT_SOURCE_DIR) + "/../shared/data/real/visp_rbt";
  if (!std::filesystem::exists(dir + "/poses.json")) GTEST_SKIP() << dir << " not present: skipped";
  const RgbdSequence s = loadRgbdSequence(dir);
  EXPECT_EQ(s.frames.size(), 50u);
  EXPECT_EQ(s.objectNames(), (std::vector<std::string>{"cube", "dragon"}));
  EXPECT_EQ(s.camera.width, 640);
  const std::vector<float> depth = loadSequenceDepth(s, s.frames.front());
  std::size_t valid = 0;
  for (float d : depth) valid += std::isfinite(d) && d > 0.1f && d < 10.0f;
  EXPECT_GT(valid, depth.size() / 2);
}

// The sequence's dragon poses refer to its mesh turned by 90 deg about x (config/real/visp_rbt.yaml
// declares it as the mesh's origin): at the given pose of frame 0, the mesh explains the measured
// depth far better with that origin than without.
TEST(RealSequence, TheDragonsMeshOriginMakesTheGivenPoseExplainTheDepth) {
  const std::string dir = std::string(SGT_SOURCE_DIR) + "/../shared/data/real/visp_rbt";
  if (!std::filesystem::exists(dir + "/poses.json")) GTEST_SKIP() << dir << " not present: skipped";
  const RgbdSequence s = loadRgbdSequence(dir);
  const RgbdSequence::Frame& f = s.frames.front();
  const RangeMeasurements m =
      fromDepthImage(s.camera, std::make_shared<const SensorRays>(makeRays(s.camera)),
                     loadSequenceDepth(s, f), Eigen::Isometry3d::Identity());
  const auto residual = [&](const std::string& catalog_file) {
    auto catalog =
        std::make_shared<const ObjectCatalog>(loadObjectCatalog(catalog_file, dir + "/models"));
    SurfaceFitter fitter(catalog, 2);
    return fitter.fit(m, {{"dragon_1", "dragon", f.T_camera_object.at("dragon")}})[0];
  };
  const SurfaceFit with = residual(std::string(SGT_SOURCE_DIR) + "/config/real/visp_rbt.yaml");
  const SurfaceFit without = residual(
      test::writeFile("visp_rbt_no_origin.yaml", "objects:\n  dragon:\n    mesh: dragon.ply\n"));
  ASSERT_GT(with.visible_pixels, 1000u);
  ASSERT_GT(without.visible_pixels, 1000u);
  EXPECT_LT(with.median_residual_m, 0.6 * without.median_residual_m)
      << with.median_residual_m << " m with the origin, " << without.median_residual_m
      << " without";
}

}  // namespace
}  // namespace sgt
