// Renders a labelled training set for the keypoint detector (YOLOv8-pose layout, DOPE cuboid
// keypoints) with the simulator's ray-cast RGB renderer and domain randomisation.
//
//   rosrun scene_graph_tracker render_dataset --output DIR --count N [--seed S] [--max-distance M]
//                                             [--bench-fraction F] [--labels object|cuboid|shape]
//                                             [--catalog FILE] [--mesh-dir D]
//                                             [--textures P] [--camera-effects P] [--photos DIR]
//                                             [--scenarios DIR [--scenario-fraction F]]
//
// Two kinds of scene: random ones (objects in any pose on a random table or the floor, any view
// from 0.5 m to M) and, for a fraction F of the images, bench scenes like the robot's (objects
// upright side by side on a wooden bench, a person nearby, the camera at head height 0.9-3.4 m
// away). F = 0 (the default) renders exactly the images of earlier versions.
//
// Appearance (simulation/appearance.hpp): --textures P patterns each surface with probability P,
// --camera-effects P gives each image a camera's exposure, white balance, gamma, blur, noise and
// JPEG with probability P; both 0 by default, which leaves the images as they were. --photos DIR
// (simulation/photo_appearance.hpp) wraps each coloured surface in one of DIR's photographs with
// probability kPhotoTextureChance and puts a photograph behind the scene (in place of the building,
// the plain walls and the void; the table, objects, distractors and people stay) in a share
// kPhotoBackgroundChance of the images. Without it the images are as they were.
//
// --scenarios DIR (evaluation/scenario_images.hpp) renders a fraction F (default 1) of the images
// as the simulator renders the frames of DIR's scenario files (e.g. `generate_scenarios` with a
// seed other than the suite's) at random times: the scenes the suite shows the detector. Camera
// effects apply to them too; textures and photographs do not (they keep the scenario's look).
//
// DIR/images/000123.png   640x480 RGB
// DIR/labels/000123.txt   per visible object: class cx cy w h x0 y0 v0 ... x8 y8 v8, normalised by
//                         the image size; box = visible pixels; keypoints in the continuous pixel
//                         convention (a pixel's centre at +0.5); v 2 inside the image (also when
//                         occluded), else 0 with x = y = 0
// DIR/poses/000123.json   scene kind (bench or random), camera K and per labelled object its class,
//                         T_camera_object and the symmetry-canonical pose the keypoints were made
//                         from
// DIR/dataset.yaml        ultralytics style; `names` are the catalog's classes in its file's order
//                         (their label ids)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <string>

#include "scene_graph_tracker/detection/keypoint_labels.hpp"
#include "scene_graph_tracker/detection/label_kind.hpp"
#include "scene_graph_tracker/evaluation/keypoint_dataset.hpp"
#include "scene_graph_tracker/evaluation/scenario_images.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/simulation/appearance.hpp"
#include "scene_graph_tracker/simulation/building.hpp"
#include "scene_graph_tracker/simulation/photo_appearance.hpp"
#include "scene_graph_tracker/simulation/rgb_render.hpp"
#include "scene_graph_tracker/util/progress_bar.hpp"

namespace fs = std::filesystem;
using Eigen::Isometry3d;
using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

constexpr int kMinVisiblePixels = 120;
constexpr sgt::NodeId kMapNode = 1, kTableNode = 2, kFirstWallNode = 10, kFirstObjectNode = 100,
                      kFirstDistractorNode = 200;
constexpr double kPlanesOrigin = -200.0;  // x of the plain-walls room, far outside the building
constexpr double kPhotoTextureChance = 0.3, kPhotoBackgroundChance = 0.5;

struct Args {
  std::string output, mesh_dir;
  std::string catalog = "package://scene_graph_tracker/config/objects.yaml";
  std::size_t count = 0;
  std::uint32_t seed = 1;
  double max_distance = 2.5;
  double bench_fraction = 0.0;
  sgt::detection::LabelKind labels = sgt::detection::LabelKind::kObject;
  double textures = 0.0;        // probability that a surface is patterned
  double camera_effects = 0.0;  // probability that an image gets camera effects
  std::string photos;           // directory of photographs (empty: none)
  bool depth = false;           // also depth/: the registered depth image (noise-free)
  std::string scenarios;        // directory of scenario files (empty: none)
  double scenario_fraction = 1.0;
};

struct Rng {
  std::mt19937 g;
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
  int integer(int a, int b) { return std::uniform_int_distribution<int>(a, b)(g); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  Vector3f colour() {
    return Vector3f(uniform(0.05, 0.95), uniform(0.05, 0.95), uniform(0.05, 0.95));
  }
  Eigen::Quaterniond rotation() {  // uniform
    Eigen::Quaterniond q(
        std::normal_distribution<double>()(g), std::normal_distribution<double>()(g),
        std::normal_distribution<double>()(g), std::normal_distribution<double>()(g));
    return q.normalized();
  }
};

// Exposure, white balance and gamma of a cheap camera, half the time blur and JPEG, and noise.
sgt::sim::CameraEffects drawCameraEffects(Rng& rng) {
  sgt::sim::CameraEffects e;
  e.gain = static_cast<float>(rng.uniform(0.6, 1.5));
  e.white_balance =
      Vector3f(rng.uniform(0.85, 1.15), rng.uniform(0.85, 1.15), rng.uniform(0.85, 1.15));
  e.gamma = static_cast<float>(rng.uniform(0.7, 1.4));
  e.blur_sigma = rng.chance(0.5) ? static_cast<float>(rng.uniform(0.3, 1.5)) : 0.0f;
  e.noise_sigma = static_cast<float>(rng.uniform(0.0, 8.0));
  e.jpeg_quality = rng.chance(0.5) ? rng.integer(40, 95) : 0;
  e.seed = static_cast<std::uint32_t>(rng.integer(0, 1 << 30));
  return e;
}

Isometry3d pose(const Eigen::Matrix3d& R, const Vector3d& t) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

Eigen::Matrix3d yaw(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix(); }

// z of the lowest corner of a box turned by R.
double lowestCorner(const Eigen::Matrix3d& R, const Eigen::AlignedBox3d& box) {
  double lowest = 1e9;
  for (int c = 0; c < 8; ++c)
    lowest =
        std::min(lowest, (R * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c))).z());
  return lowest;
}

// Meshes registered once; every image instances some of them.
struct Library {
  std::vector<sgt::MeshId> classes, tables, distractors, benches, persons;
  std::vector<Eigen::AlignedBox3d> class_boxes, table_boxes, bench_boxes;
  std::vector<double> person_heights;
  sgt::MeshId wall = -1;
};

// One image's randomised scene: what was placed, for labelling.
struct Placed {
  int class_id;
  sgt::NodeId node;
  Isometry3d T_world_object;
};

class DatasetRenderer {
 public:
  DatasetRenderer(const sgt::ObjectCatalog& catalog, const Args& args)
      : catalog_(catalog),
        classes_(catalog.listed()),
        seed_(args.seed),
        max_distance_(args.max_distance),
        bench_fraction_(args.bench_fraction),
        labels_(args.labels),
        textures_(args.textures),
        camera_effects_(args.camera_effects),
        depth_(args.depth),
        photos_(args.photos.empty() ? decltype(photos_){} : sgt::sim::loadPhotos(args.photos)) {
    if (!args.photos.empty() && photos_.empty())
      throw std::runtime_error("no readable .jpg or .png under " + args.photos);
    const std::uint32_t seed = seed_;
    sgt::BuildingOptions b;
    b.length_x = 24.0f, b.length_y = 20.0f, b.rooms_x = 3, b.rooms_y = 2,
    b.target_triangles = 80000, b.seed = seed;
    building_ = sgt::makeBuilding(b);
    scene_.setStaticMap(std::make_shared<sgt::TriangleMesh>(building_.mesh), kMapNode);
    Rng rng{std::mt19937(seed ^ 0x5eedu)};
    for (const auto& name : classes_) {
      const auto& c = catalog_.get(name);
      lib_.classes.push_back(scene_.addMesh(c.mesh));
      lib_.class_boxes.push_back(c.box.cast<double>());
    }
    for (int i = 0; i < 10; ++i) {
      const Vector3f size(rng.uniform(0.5, 1.8), rng.uniform(0.4, 1.0), rng.uniform(0.4, 1.0));
      lib_.tables.push_back(
          scene_.addMesh(std::make_shared<sgt::TriangleMesh>(sgt::makeBox(size))));
      lib_.table_boxes.emplace_back(-0.5 * size.cast<double>(), 0.5 * size.cast<double>());
    }
    for (int i = 0; i < 24; ++i) {
      std::shared_ptr<sgt::TriangleMesh> m;
      if (i % 3 == 0)
        m = std::make_shared<sgt::TriangleMesh>(sgt::makeBox(
            Vector3f(rng.uniform(0.02, 0.3), rng.uniform(0.02, 0.3), rng.uniform(0.02, 0.3))));
      else if (i % 3 == 1)
        m = std::make_shared<sgt::TriangleMesh>(
            sgt::makeCylinder(rng.uniform(0.01, 0.1), rng.uniform(0.03, 0.35), 24));
      else
        m = std::make_shared<sgt::TriangleMesh>(sgt::makeSphere(rng.uniform(0.015, 0.12), 24, 12));
      lib_.distractors.push_back(scene_.addMesh(m));
    }
    lib_.wall = scene_.addMesh(
        std::make_shared<sgt::TriangleMesh>(sgt::makeBox(Vector3f(40.0f, 40.0f, 0.02f))));
    // Bench scenes: workbench-sized tables (the demo's is 1.6 x 0.8 x 0.75 m) and people.
    for (const Vector3f& size :
         {Vector3f(1.6f, 0.8f, 0.75f), Vector3f(1.2f, 0.7f, 0.72f), Vector3f(2.0f, 0.9f, 0.9f),
          Vector3f(1.4f, 0.6f, 0.8f), Vector3f(1.8f, 0.75f, 0.78f)}) {
      lib_.benches.push_back(
          scene_.addMesh(std::make_shared<sgt::TriangleMesh>(sgt::makeBox(size))));
      lib_.bench_boxes.emplace_back(-0.5 * size.cast<double>(), 0.5 * size.cast<double>());
    }
    for (const double h : {1.6, 1.75, 1.9}) {
      lib_.persons.push_back(scene_.addMesh(std::make_shared<sgt::TriangleMesh>(
          sgt::makeCylinder(0.25f, static_cast<float>(h), 48))));
      lib_.person_heights.push_back(h);
    }
    colours_.static_map = kMapNode;
    camera_.width = 640, camera_.height = 480;
    for (const auto& name : classes_) label_symmetry_.push_back(labelSymmetry(catalog_.get(name)));
  }

  void render(std::size_t index, const fs::path& dir);
  const std::vector<sgt::Symmetry>& labelSymmetries() const { return label_symmetry_; }

 private:
  Vector3d placeSupport(Rng& rng, double& top, Eigen::Vector2d& half, bool bench);
  void placeObjects(Rng& rng, double top, const Vector3d& centre, const Eigen::Vector2d& half);
  void placeBenchObjects(Rng& rng, double top, const Vector3d& centre, const Eigen::Vector2d& half);
  void addObject(Rng& rng, int cls, sgt::NodeId node, const Isometry3d& T_world_object,
                 double random_colour, double jitter);
  Isometry3d placeCamera(Rng& rng, const Vector3d& target);
  Isometry3d placeBenchCamera(Rng& rng, const Vector3d& target, double top);
  void placePerson(Rng& rng, const Vector3d& centre, double top);
  bool insideRoom(const Vector3d& eye) const;
  void clear();
  void writeLabels(std::size_t index, const fs::path& dir, const Isometry3d& T_world_camera,
                   const sgt::SimulatedScan& scan);
  std::vector<sgt::NodeId> colouredNodes() const;
  void randomisePatterns(Rng& rng);
  sgt::Symmetry labelSymmetry(const sgt::ObjectClass& oc) const;
  void wrapInPhotos(Rng& rng);
  void putPhotoBehind(Rng& rng, cv::Mat& bgr, const sgt::SimulatedScan& scan) const;

  const sgt::ObjectCatalog& catalog_;
  const std::vector<std::string> classes_;  // label id -> class name
  std::uint32_t seed_;
  double max_distance_;  // camera to the objects' centre, from 0.5 m
  double bench_fraction_;
  bool bench_ = false;  // the current image is a bench scene
  sgt::detection::LabelKind labels_;
  std::vector<sgt::Symmetry>
      label_symmetry_;  // per class: the symmetries its labels are taken up to
  double textures_, camera_effects_;
  bool depth_;
  std::vector<std::shared_ptr<const cv::Mat>> photos_;
  sgt::Building building_;
  sgt::RaycastScene scene_;
  Library lib_;
  sgt::sim::NodeColours colours_;
  sgt::PinholeModel camera_;
  std::vector<Placed> placed_;
  std::vector<sgt::NodeId> extra_nodes_;  // table, walls, distractors of the current image
  bool in_building_ = true;
  Eigen::AlignedBox3f room_;
};

void DatasetRenderer::clear() {
  for (const auto& p : placed_) scene_.removeInstance(p.node);
  for (const auto n : extra_nodes_) scene_.removeInstance(n);
  placed_.clear(), extra_nodes_.clear();
  colours_.albedo.clear();
  colours_.patterns.clear();
  colours_.photos.clear();
}

// The nodes with a colour (objects, table, walls, distractors, people), in a fixed order so that a
// seed draws the same appearance for each.
std::vector<sgt::NodeId> DatasetRenderer::colouredNodes() const {
  std::vector<sgt::NodeId> nodes;
  for (const auto& [node, albedo] : colours_.albedo) nodes.push_back(node);
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

// Each coloured surface (objects, table, walls, distractors, people) patterned with probability
// textures_: checker, stripes, smooth noise or blotches in a second random colour, 3 mm to 8 cm.
void DatasetRenderer::randomisePatterns(Rng& rng) {
  for (const sgt::NodeId node : colouredNodes()) {
    if (!rng.chance(textures_)) continue;
    sgt::sim::SurfacePattern p;
    p.kind = static_cast<sgt::sim::SurfacePattern::Kind>(rng.integer(0, 3));
    p.second = rng.colour();
    p.scale = static_cast<float>(std::exp(rng.uniform(std::log(0.003), std::log(0.08))));
    p.direction = Vector3f(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    p.direction = p.direction.norm() > 1e-3f ? p.direction.normalized() : Vector3f::UnitX();
    p.seed = static_cast<std::uint32_t>(rng.integer(0, 1 << 30));
    colours_.patterns[node] = p;
  }
}

// The symmetries the class's labels are taken up to (detection/label_kind.hpp), saying which turns
// shape labels add.
sgt::Symmetry DatasetRenderer::labelSymmetry(const sgt::ObjectClass& oc) const {
  const sgt::Symmetry s = sgt::detection::labelSymmetry(oc, labels_);
  if (s.discrete.size() > oc.symmetry.discrete.size())
    std::cerr << "render_dataset: " << oc.name << " labelled up to "
              << s.discrete.size() - oc.symmetry.discrete.size()
              << " turns of its box that look alike\n";
  return s;
}

// Each coloured surface wrapped in a photograph with probability kPhotoTextureChance, spanning
// 3 cm to 1 m.
void DatasetRenderer::wrapInPhotos(Rng& rng) {
  for (const sgt::NodeId node : colouredNodes()) {
    if (!rng.chance(kPhotoTextureChance)) continue;
    sgt::sim::PhotoTexture t;
    t.image = photos_[rng.integer(0, static_cast<int>(photos_.size()) - 1)];
    t.size_m = static_cast<float>(std::exp(rng.uniform(std::log(0.03), std::log(1.0))));
    t.offset_m = Eigen::Vector2f(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
    colours_.photos[node] = t;
  }
}

// The pixels of the building, the plain walls and the void replaced by a view of a photograph.
void DatasetRenderer::putPhotoBehind(Rng& rng, cv::Mat& bgr, const sgt::SimulatedScan& scan) const {
  const cv::Mat& photo = *photos_[rng.integer(0, static_cast<int>(photos_.size()) - 1)];
  const cv::Mat view =
      sgt::sim::photoView(photo, bgr.size(), rng.uniform(1.0, 3.0), rng.uniform(0.0, 1.0),
                          rng.uniform(0.0, 1.0), rng.chance(0.5));
  cv::Mat behind(bgr.size(), CV_8U);
  for (int v = 0; v < bgr.rows; ++v)
    for (int u = 0; u < bgr.cols; ++u) {
      const sgt::NodeId n = scan.node[static_cast<std::size_t>(v) * scan.width + u];
      behind.at<std::uint8_t>(v, u) =
          n == sgt::kNoNode || n == kMapNode || (n >= kFirstWallNode && n < kFirstObjectNode);
    }
  view.copyTo(bgr, behind);
}

// A table (or the bare floor) in a random building room or in a room of plain coloured walls;
// for a bench scene always a bench, mostly wooden and in the building.
// Returns the centre of the support's top; `half` its half extents in x, y (world, axis-aligned).
Vector3d DatasetRenderer::placeSupport(Rng& rng, double& top, Eigen::Vector2d& half, bool bench) {
  in_building_ = rng.chance(bench ? 0.7 : 0.5);
  Vector3d centre;
  if (in_building_) {
    room_ = building_.rooms[rng.integer(0, static_cast<int>(building_.rooms.size()) - 1)];
    centre = Vector3d(rng.uniform(room_.min().x() + 1.0, room_.max().x() - 1.0),
                      rng.uniform(room_.min().y() + 1.0, room_.max().y() - 1.0), 0.0);
  } else {
    centre = Vector3d(kPlanesOrigin, 0.0, 0.0);
    const double a = rng.uniform(0.0, 2.0 * M_PI);
    const double h = rng.uniform(3.2, 5.0);
    for (int w = 0; w < 6; ++w) {  // floor, ceiling, four walls at random distances
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      Vector3d t = centre;
      if (w == 1) t.z() = h;
      if (w >= 2) {
        R = yaw(a + (w - 2) * M_PI / 2) *
            Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
        t += yaw(a + (w - 2) * M_PI / 2) * Vector3d(rng.uniform(2.8, 6.0), 0.0, 0.0);
      }
      scene_.addInstance(kFirstWallNode + w, lib_.wall, pose(R, t));
      colours_.albedo[kFirstWallNode + w] = rng.colour();
      extra_nodes_.push_back(kFirstWallNode + w);
    }
  }
  top = 0.0;
  half = Eigen::Vector2d(rng.uniform(0.4, 0.8), rng.uniform(0.4, 0.8));
  if (bench || rng.chance(0.85)) {  // a table; otherwise the objects lie on the floor
    const auto& meshes = bench ? lib_.benches : lib_.tables;
    const int k = rng.integer(0, static_cast<int>(meshes.size()) - 1);
    const Eigen::AlignedBox3d& b = bench ? lib_.bench_boxes[k] : lib_.table_boxes[k];
    const bool turned = rng.chance(0.5);  // quarter turns keep the top axis-aligned
    top = b.max().z() - b.min().z();
    half = turned ? Eigen::Vector2d(b.max().y(), b.max().x())
                  : Eigen::Vector2d(b.max().x(), b.max().y());
    scene_.addInstance(kTableNode, meshes[k],
                       pose(yaw(turned ? M_PI / 2 : 0.0), centre + Vector3d(0, 0, top / 2)));
    colours_.albedo[kTableNode] = rng.chance(bench ? 0.75 : 0.4)
                                      ? Vector3f(0.62f, 0.45f, 0.28f) * rng.uniform(0.7, 1.2)
                                      : rng.colour();
    extra_nodes_.push_back(kTableNode);
  }
  return centre + Vector3d(0, 0, top);
}

// A catalog object in its class colour, varied by up to +-jitter per channel, or with probability
// random_colour in a random one; labelled.
void DatasetRenderer::addObject(Rng& rng, int cls, sgt::NodeId node,
                                const Isometry3d& T_world_object, double random_colour,
                                double jitter) {
  scene_.addInstance(node, lib_.classes[cls], T_world_object);
  // The catalog's colour, else the built-in one; a class of unknown colour gets a random one,
  // drawn after the same chance so that the scene's other draws stay as they are.
  const std::optional<Vector3f>& declared = catalog_.get(classes_[cls]).colour;
  const std::optional<Vector3f> known =
      declared ? declared : sgt::sim::knownClassColour(classes_[cls]);
  Vector3f c = known.value_or(Vector3f::Zero());
  if (rng.chance(random_colour) || !known)
    c = rng.colour();
  else
    c = (c + Vector3f(rng.uniform(-jitter, jitter), rng.uniform(-jitter, jitter),
                      rng.uniform(-jitter, jitter)))
            .cwiseMax(0.02f)
            .cwiseMin(1.0f);
  colours_.albedo[node] = c;
  placed_.push_back({cls, node, T_world_object});
}

// 1-6 catalog objects (sometimes several of a class): mostly resting on a face in a random yaw,
// some in a random orientation; 0-6 distractor primitives.
void DatasetRenderer::placeObjects(Rng& rng, double top, const Vector3d& centre,
                                   const Eigen::Vector2d& half) {
  const int n = rng.integer(1, 6);
  auto onSupport = [&](const Eigen::Matrix3d& R, const Eigen::AlignedBox3d& box) {
    const double lowest = lowestCorner(R, box);
    return Vector3d(centre.x() + rng.uniform(-half.x(), half.x()) * 0.9,
                    centre.y() + rng.uniform(-half.y(), half.y()) * 0.9, top - lowest);
  };
  for (int i = 0; i < n; ++i) {
    const int cls = rng.integer(0, static_cast<int>(classes_.size()) - 1);
    Eigen::Matrix3d R;
    if (rng.chance(0.75)) {  // resting on one of its six faces
      static const Eigen::Matrix3d faces[6] = {
          Eigen::Matrix3d::Identity(),
          Eigen::AngleAxisd(M_PI, Vector3d::UnitX()).toRotationMatrix(),
          Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()).toRotationMatrix(),
          Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitX()).toRotationMatrix(),
          Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix(),
          Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitY()).toRotationMatrix()};
      R = yaw(rng.uniform(0, 2 * M_PI)) * faces[rng.chance(0.5) ? 0 : rng.integer(0, 5)];
    } else {
      R = rng.rotation().toRotationMatrix();
    }
    Vector3d t = onSupport(R, lib_.class_boxes[cls]);
    if (R(2, 2) < 0.99 && rng.chance(0.3)) t.z() += rng.uniform(0.0, 0.3);  // held or stacked
    addObject(rng, cls, kFirstObjectNode + i, pose(R, t), 0.15, 0.1);
  }
  const int d = rng.integer(0, 6);
  for (int i = 0; i < d; ++i) {
    const int k = rng.integer(0, static_cast<int>(lib_.distractors.size()) - 1);
    const Eigen::Matrix3d R =
        rng.chance(0.6) ? yaw(rng.uniform(0, 2 * M_PI)) : rng.rotation().toRotationMatrix();
    const Eigen::AlignedBox3d box = scene_.mesh(lib_.distractors[k]).boundingBox().cast<double>();
    const sgt::NodeId node = kFirstDistractorNode + i;
    scene_.addInstance(node, lib_.distractors[k], pose(R, onSupport(R, box)));
    colours_.albedo[node] = rng.colour();
    extra_nodes_.push_back(node);
  }
}

// 2-6 objects (each class at most once until all five are there) on the bench, most upright as in
// the catalog in a random yaw, apart from each other; some lifted as if held; 0-3 distractor
// primitives between them.
void DatasetRenderer::placeBenchObjects(Rng& rng, double top, const Vector3d& centre,
                                        const Eigen::Vector2d& half) {
  std::vector<int> order = {0, 1, 2, 3, 4};
  std::shuffle(order.begin(), order.end(), rng.g);
  std::vector<Eigen::Vector3d> taken;  // x, y, footprint radius
  auto freeSpot = [&](double radius, Vector3d& at) {
    for (int attempt = 0; attempt < 30; ++attempt) {
      at = Vector3d(centre.x() + rng.uniform(-half.x(), half.x()) * 0.85,
                    centre.y() + rng.uniform(-half.y(), half.y()) * 0.85, 0.0);
      bool clear = true;
      for (const auto& o : taken)
        clear = clear && (at.head<2>() - o.head<2>()).norm() > 0.8 * (radius + o.z());
      if (clear) return taken.emplace_back(at.x(), at.y(), radius), true;
    }
    return false;
  };
  const int n = rng.integer(2, 6);
  for (int i = 0; i < n; ++i) {
    const int cls = i < 5 ? order[i] : rng.integer(0, 4);
    Eigen::Matrix3d R = yaw(rng.uniform(0, 2 * M_PI));
    if (rng.chance(0.15))
      R = R * Eigen::AngleAxisd(rng.chance(0.5) ? M_PI / 2 : -M_PI / 2,
                                rng.chance(0.5) ? Vector3d::UnitX() : Vector3d::UnitY());
    const Eigen::AlignedBox3d& box = lib_.class_boxes[cls];
    Vector3d t;
    if (!freeSpot(0.5 * box.sizes().head<2>().norm(), t)) continue;
    t.z() = top - lowestCorner(R, box) + 0.001;
    if (rng.chance(0.1)) t.z() += rng.uniform(0.03, 0.3);  // held
    addObject(rng, cls, kFirstObjectNode + i, pose(R, t), 0.05, 0.06);
  }
  const int d = rng.integer(0, 3);
  for (int i = 0; i < d; ++i) {
    const int k = rng.integer(0, static_cast<int>(lib_.distractors.size()) - 1);
    const Eigen::Matrix3d R = yaw(rng.uniform(0, 2 * M_PI));
    const Eigen::AlignedBox3d box = scene_.mesh(lib_.distractors[k]).boundingBox().cast<double>();
    Vector3d t;
    if (!freeSpot(0.5 * box.sizes().head<2>().norm(), t)) continue;
    t.z() = top - box.min().z() + 0.001;
    const sgt::NodeId node = kFirstDistractorNode + i;
    scene_.addInstance(node, lib_.distractors[k], pose(R, t));
    colours_.albedo[node] = rng.colour();
    extra_nodes_.push_back(node);
  }
}

// A person (a cylinder on the floor) 0.4-1.4 m from the bench's centre, in 40 % of bench scenes.
void DatasetRenderer::placePerson(Rng& rng, const Vector3d& centre, double top) {
  if (!rng.chance(0.4)) return;
  const int k = rng.integer(0, static_cast<int>(lib_.persons.size()) - 1);
  const double a = rng.uniform(0, 2 * M_PI), r = rng.uniform(0.4, 1.4);
  const Vector3d at =
      centre + Vector3d(r * std::cos(a), r * std::sin(a), -top + 0.5 * lib_.person_heights[k]);
  const sgt::NodeId node = kFirstDistractorNode + 10;
  scene_.addInstance(node, lib_.persons[k], pose(Eigen::Matrix3d::Identity(), at));
  colours_.albedo[node] = rng.colour() * 0.6f;
  extra_nodes_.push_back(node);
}

bool DatasetRenderer::insideRoom(const Vector3d& eye) const {
  return !in_building_ || (eye.x() > room_.min().x() + 0.15 && eye.x() < room_.max().x() - 0.15 &&
                           eye.y() > room_.min().y() + 0.15 && eye.y() < room_.max().y() - 0.15 &&
                           eye.z() < room_.max().z() - 0.15);
}

// A robot's head camera: 0.9-3.4 m (horizontal) from a point on the bench, 0.3-0.75 m above its
// top (at world height `top`; floors are at z = 0), little roll.
Isometry3d DatasetRenderer::placeBenchCamera(Rng& rng, const Vector3d& target, double top) {
  for (int attempt = 0;; ++attempt) {
    const double d = rng.uniform(0.9, 3.4), az = rng.uniform(0, 2 * M_PI);
    const Vector3d eye(target.x() + d * std::cos(az), target.y() + d * std::sin(az),
                       top + rng.uniform(0.3, 0.75));
    if (!insideRoom(eye) && attempt < 50) continue;
    Isometry3d T = sgt::opticalLookAt(eye, target);
    T.linear() = T.linear() *
                 Eigen::AngleAxisd(rng.uniform(-0.05, 0.05), Vector3d::UnitZ()).toRotationMatrix();
    return T;
  }
}

// 0.5 m to max_distance_ from a point near the objects, looking down 10-60 degrees, some roll.
Isometry3d DatasetRenderer::placeCamera(Rng& rng, const Vector3d& target) {
  for (int attempt = 0;; ++attempt) {
    const double d = rng.uniform(0.5, max_distance_), el = rng.uniform(10.0, 60.0) * M_PI / 180.0,
                 az = rng.uniform(0, 2 * M_PI);
    const Vector3d eye = target + d * Vector3d(std::cos(el) * std::cos(az),
                                               std::cos(el) * std::sin(az), std::sin(el));
    if (!insideRoom(eye) && attempt < 50) continue;
    Isometry3d T = sgt::opticalLookAt(eye, target);
    T.linear() = T.linear() *
                 Eigen::AngleAxisd(rng.uniform(-0.35, 0.35), Vector3d::UnitZ()).toRotationMatrix();
    return T;
  }
}

void DatasetRenderer::render(std::size_t index, const fs::path& dir) {
  Rng rng{std::mt19937(static_cast<std::uint32_t>(seed_ * 2654435761u + index * 40503u + 17u))};
  // Drawn from its own stream, so that --bench-fraction 0 leaves the random scenes as they were.
  bench_ = bench_fraction_ > 0.0 &&
           Rng{std::mt19937(static_cast<std::uint32_t>(seed_ * 97u + index * 7919u + 3u))}.chance(
               bench_fraction_);
  const bool bench = bench_;
  clear();
  double top = 0.0;
  Eigen::Vector2d half;
  const Vector3d centre = placeSupport(rng, top, half, bench);
  if (bench)
    placeBenchObjects(rng, top, centre, half), placePerson(rng, centre, top);
  else
    placeObjects(rng, top, centre, half);
  scene_.commit();
  Vector3d target = Vector3d::Zero();
  for (const auto& p : placed_) target += p.T_world_object.translation();
  if (placed_.empty())
    target = centre;
  else
    target /= static_cast<double>(placed_.size());
  Isometry3d T_world_camera;
  sgt::sim::RenderStyle style;
  if (bench) {  // the demo's camera and light (README, "Scenario format"), a little varied
    target = Vector3d(target.x() + rng.uniform(-0.3, 0.3), target.y() + rng.uniform(-0.3, 0.3),
                      top + rng.uniform(-0.1, 0.1));
    camera_.fx = camera_.fy = rng.uniform(500.0, 560.0);
    camera_.cx = 319.5 + rng.uniform(-4, 4), camera_.cy = 239.5 + rng.uniform(-4, 4);
    T_world_camera = placeBenchCamera(rng, target, top);
    style.light_direction =
        (style.light_direction + Vector3f(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), 0.0f))
            .normalized();
    style.ambient = rng.uniform(0.25, 0.45), style.diffuse = rng.uniform(0.3, 0.6),
    style.headlight = rng.uniform(0.1, 0.35);
    style.floor_tile = rng.uniform(0.4, 0.6);
  } else {
    target += Vector3d(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.05, 0.1));
    camera_.fx = camera_.fy = rng.uniform(480.0, 620.0);
    camera_.cx = 319.5 + rng.uniform(-8, 8), camera_.cy = 239.5 + rng.uniform(-8, 8);
    T_world_camera = placeCamera(rng, target);
    style.light_direction =
        Vector3f(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.2, 1.0)).normalized();
    style.ambient = rng.uniform(0.15, 0.5), style.diffuse = rng.uniform(0.2, 0.7),
    style.headlight = rng.uniform(0.0, 0.4);
    style.background = rng.colour() * 0.3f;
    style.floor_tile = rng.uniform(0.2, 0.8);
  }
  // Appearance is drawn from a stream of its own, so that without it the scenes stay as they were.
  Rng looks{std::mt19937(static_cast<std::uint32_t>(seed_ * 31337u + index * 104729u + 11u))};
  if (textures_ > 0.0) randomisePatterns(looks);
  // Photographs from a third stream, so that without them the images stay as they were.
  Rng shots{std::mt19937(static_cast<std::uint32_t>(seed_ * 7907u + index * 15485863u + 29u))};
  if (!photos_.empty()) wrapInPhotos(shots);
  const sgt::SensorRays rays = sgt::makeRays(camera_);
  const sgt::SimulatedScan scan = sgt::simulate(scene_, rays, T_world_camera);
  const std::vector<std::uint8_t> rgb = sgt::sim::renderRgb(scan, T_world_camera, colours_, style);
  cv::Mat bgr;
  cv::cvtColor(
      cv::Mat(camera_.height, camera_.width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data())), bgr,
      cv::COLOR_RGB2BGR);
  if (!photos_.empty() && shots.chance(kPhotoBackgroundChance)) putPhotoBehind(shots, bgr, scan);
  if (camera_effects_ > 0.0 && looks.chance(camera_effects_))
    sgt::sim::applyCameraEffects(bgr, drawCameraEffects(looks));
  cv::imwrite((dir / "images" / (sgt::datasetFrameName(index) + ".png")).string(), bgr);
  if (depth_)
    sgt::writeDatasetDepth(dir, index, sgt::depthImage(scan, rays), camera_.width, camera_.height);
  writeLabels(index, dir, T_world_camera, scan);
}

void DatasetRenderer::writeLabels(std::size_t index, const fs::path& dir,
                                  const Isometry3d& T_world_camera,
                                  const sgt::SimulatedScan& scan) {
  struct Visible {
    int pixels = 0, x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  };
  std::map<sgt::NodeId, Visible> vis;
  for (int v = 0; v < scan.height; ++v)
    for (int u = 0; u < scan.width; ++u) {
      const sgt::NodeId n = scan.node[static_cast<std::size_t>(v) * scan.width + u];
      if (n < kFirstObjectNode || n >= kFirstDistractorNode) continue;
      Visible& s = vis[n];
      ++s.pixels, s.x0 = std::min(s.x0, u), s.y0 = std::min(s.y0, v), s.x1 = std::max(s.x1, u),
                  s.y1 = std::max(s.y1, v);
    }
  std::vector<sgt::DatasetObject> objects;
  for (const auto& p : placed_) {
    const auto it = vis.find(p.node);
    if (it == vis.end() || it->second.pixels < kMinVisiblePixels) continue;
    const Visible& s = it->second;
    const Isometry3d T = T_world_camera.inverse() * p.T_world_object;
    const sgt::Symmetry& sym = label_symmetry_[p.class_id];
    const Isometry3d T_label = sgt::detection::labelPose(T, sym, labels_);
    objects.push_back({p.class_id, classes_[p.class_id], s.pixels, s.x0, s.y0, s.x1, s.y1, T,
                       T_label, lib_.class_boxes[p.class_id]});
  }
  sgt::writeDatasetLabels(dir, index, bench_ ? "bench" : "random", camera_, objects);
}

void usage(std::ostream& os) {
  os << "usage: render_dataset --output DIR --count N [--seed S] [--max-distance M] [--mesh-dir "
        "D]\n"
        "  --output    dataset directory (images/, labels/, poses/, dataset.yaml)\n"
        "  --count     number of images\n"
        "  --seed      random seed (default 1); the same seed renders the same images\n"
        "  --max-distance  camera distances are drawn from 0.5 m to M (default 2.5)\n"
        "  --bench-fraction  this fraction of the images (0-1, default 0) are bench scenes like "
        "the robot's\n"
        "  --labels    object (default): keypoints of the pose up to the object's symmetries; "
        "cuboid: up to\n"
        "              a half turn of its box as well (detection/keypoint_labels.hpp); shape: "
        "up to the\n"
        "              turns of its box that leave its surface where it was (a plain cube's 24)\n"
        "  --catalog   object catalog whose classes are rendered, in its order (default the "
        "package's\n"
        "              config/objects.yaml)\n"
        "  --mesh-dir  use the meshes in D for the catalog classes\n"
        "  --textures P        each surface patterned (checker, stripes, noise, blotches) with "
        "probability P\n"
        "                      (default 0)\n"
        "  --camera-effects P  each image given exposure, white balance, gamma, blur, noise and "
        "JPEG with\n"
        "                      probability P (default 0)\n"
        "  --photos DIR        photographs (.jpg, .png under DIR) as surface textures and "
        "backgrounds\n"
        "                      (make photos fetches a set)\n"
        "  --scenarios DIR     render frames of DIR's scenario files (generate_scenarios) at "
        "random times\n"
        "  --scenario-fraction F  this fraction of the images (0-1, default 1) come from "
        "--scenarios\n";
}

// Whether image `index` comes from the scenarios: drawn from a stream of its own, so that the
// other images stay as they were.
bool fromScenario(const Args& args, std::size_t index) {
  return Rng{std::mt19937(static_cast<std::uint32_t>(args.seed * 613u + index * 1299709u + 41u))}
      .chance(args.scenario_fraction);
}

std::unique_ptr<sgt::ScenarioImages> scenarioImages(const sgt::ObjectCatalog& catalog,
                                                    const DatasetRenderer& renderer,
                                                    const Args& args) {
  if (args.scenarios.empty()) return nullptr;
  return std::make_unique<sgt::ScenarioImages>(sgt::scenarioFiles(args.scenarios), catalog.listed(),
                                               renderer.labelSymmetries(), args.labels,
                                               args.mesh_dir, kMinVisiblePixels);
}

void renderScenarioImage(sgt::ScenarioImages& scenarios, const Args& args, std::size_t index,
                         const fs::path& dir) {
  sgt::ScenarioImage image = scenarios.render(index, args.count, args.seed);
  Rng looks{std::mt19937(static_cast<std::uint32_t>(args.seed * 31337u + index * 104729u + 11u))};
  if (args.camera_effects > 0.0 && looks.chance(args.camera_effects))
    sgt::sim::applyCameraEffects(image.bgr, drawCameraEffects(looks));
  cv::imwrite((dir / "images" / (sgt::datasetFrameName(index) + ".png")).string(), image.bgr);
  sgt::writeDatasetLabels(dir, index, "scenario", image.camera, image.objects);
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage(std::cout), 0;
    if (i + 1 >= argc)
      return std::cerr << "render_dataset: " << a << " needs a value\n", usage(std::cerr), 2;
    const std::string v = argv[++i];
    if (a == "--output")
      args.output = v;
    else if (a == "--count")
      args.count = std::stoul(v);
    else if (a == "--seed")
      args.seed = static_cast<std::uint32_t>(std::stoul(v));
    else if (a == "--mesh-dir")
      args.mesh_dir = v;
    else if (a == "--catalog")
      args.catalog = v;
    else if (a == "--max-distance")
      args.max_distance = std::stod(v);
    else if (a == "--bench-fraction")
      args.bench_fraction = std::stod(v);
    else if (a == "--textures")
      args.textures = std::stod(v);
    else if (a == "--camera-effects")
      args.camera_effects = std::stod(v);
    else if (a == "--photos")
      args.photos = v;
    else if (a == "--scenarios")
      args.scenarios = v;
    else if (a == "--scenario-fraction")
      args.scenario_fraction = std::stod(v);
    else if (a == "--depth")
      args.depth = v == "1";
    else if (a == "--labels") {
      const auto kind = sgt::detection::parseLabelKind(v);
      if (!kind)
        return std::cerr << "render_dataset: --labels is object, cuboid or shape, not '" << v
                         << "'\n",
               2;
      args.labels = *kind;
    } else
      return std::cerr << "render_dataset: unknown argument '" << a << "'\n", usage(std::cerr), 2;
  }
  if (args.output.empty() || args.count == 0 || !(args.max_distance > 0.5) ||
      !(args.bench_fraction >= 0.0 && args.bench_fraction <= 1.0) ||
      !(args.textures >= 0.0 && args.textures <= 1.0) ||
      !(args.camera_effects >= 0.0 && args.camera_effects <= 1.0) ||
      !(args.scenario_fraction >= 0.0 && args.scenario_fraction <= 1.0))
    return usage(std::cerr), 2;
  if (!args.scenarios.empty() && args.depth)
    return std::cerr << "render_dataset: --depth is not available with --scenarios\n", 2;
  try {
    const fs::path dir = fs::absolute(args.output);
    for (const char* sub : {"images", "labels", "poses"}) fs::create_directories(dir / sub);
    const sgt::ObjectCatalog catalog = sgt::loadObjectCatalog(args.catalog, args.mesh_dir);
    DatasetRenderer renderer(catalog, args);
    std::unique_ptr<sgt::ScenarioImages> scenarios = scenarioImages(catalog, renderer, args);
    sgt::ProgressBar bar("render_dataset", args.count);
    for (std::size_t i = 0; i < args.count; ++i) {
      if (scenarios && fromScenario(args, i))
        renderScenarioImage(*scenarios, args, i, dir);
      else
        renderer.render(i, dir);
      bar.update(i + 1);
    }
    bar.finish();
    std::ostringstream comment;
    comment << "rendered by render_dataset --count " << args.count << " --seed " << args.seed
            << " --max-distance " << args.max_distance << " --bench-fraction "
            << args.bench_fraction << " --labels " << sgt::detection::labelKindName(args.labels)
            << " --catalog " << args.catalog << " --textures " << args.textures
            << " --camera-effects " << args.camera_effects << " --depth " << args.depth;
    if (!args.photos.empty()) comment << " --photos " << args.photos;
    if (!args.scenarios.empty())
      comment << " --scenarios " << args.scenarios << " --scenario-fraction "
              << args.scenario_fraction;
    sgt::writeDatasetYaml(dir, comment.str(), catalog.listed());
  } catch (const std::exception& e) {
    std::cerr << "render_dataset: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
