// PointCloud2 -> ranges (sgt::ros::measurementsFromCloud): a cloud whose fields, offsets,
// datatypes, point_step, row_step, width, height, endianness and data all come from the bytes,
// against a LiDAR model from the tracker's parameters (assemblerOptions). The bytes: the layout
// (taken from the end), then the point data (from the front). A consistent layout (row_step and
// data sized to width x height) is picked often so the points themselves get read.
#include <sensor_msgs/PointField.h>

#include <algorithm>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/frame_assembler.hpp"

namespace {

using sgt::fuzz::count;
using sgt::fuzz::name;

// The model as the tracker makes it from lidar/* (parameter ranges of the schema); small models
// often, so that organized clouds of the model's size are within reach.
sgt::SpinningLidarModel lidarModel(FuzzedDataProvider& p) {
  sgt::params::TrackerNodeOptions node;
  if (p.ConsumeBool()) {
    node.lidar.columns = p.ConsumeIntegralInRange<int>(1, p.ConsumeBool() ? 8 : 2048);
    node.lidar.rings = p.ConsumeIntegralInRange<int>(1, p.ConsumeBool() ? 4 : 128);
    node.lidar.phi_min = p.ConsumeFloatingPointInRange(-1.5708, 1.5708);
    node.lidar.phi_max = p.ConsumeFloatingPointInRange(-1.5708, 1.5708);
  }
  return sgt::ros::assemblerOptions(node).lidar;  // throws std::invalid_argument: no sensor
}

sensor_msgs::PointField field(FuzzedDataProvider& p, std::uint32_t point_step) {
  sensor_msgs::PointField f;
  f.name = name(p, {"x", "y", "z", "intensity", "ring"});
  f.offset = p.ConsumeBool() ? 4 * p.ConsumeIntegralInRange<std::uint32_t>(0, 7)
                             : count<std::uint32_t>(p, point_step + 4);
  f.datatype = p.ConsumeBool() ? std::uint8_t{sensor_msgs::PointField::FLOAT32}
                               : p.ConsumeIntegral<std::uint8_t>();
  f.count = p.ConsumeBool() ? 1 : p.ConsumeIntegral<std::uint32_t>();
  return f;
}

}  // namespace

int sgtFuzzCloud(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  sgt::SpinningLidarModel model;
  try {
    model = lidarModel(p);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  sensor_msgs::PointCloud2 cloud;
  const bool organized = p.ConsumeIntegralInRange<int>(0, 3) == 0;
  cloud.height = organized ? model.rings : count<std::uint32_t>(p, 4);
  cloud.width = organized ? model.columns : count<std::uint32_t>(p, 64);
  cloud.point_step = p.ConsumeBool() ? 4 * p.ConsumeIntegralInRange<std::uint32_t>(3, 8)
                                     : count<std::uint32_t>(p, 64);
  cloud.is_bigendian = p.ConsumeBool();
  cloud.is_dense = p.ConsumeBool();
  const int fields = p.ConsumeIntegralInRange<int>(0, 6);
  for (int k = 0; k < fields; ++k) cloud.fields.push_back(field(p, cloud.point_step));
  // Consistent rows and data (the harness itself allocates at most 1 MB), or anything.
  const std::uint64_t row = std::uint64_t(cloud.width) * cloud.point_step;
  const std::uint64_t consistent = row * cloud.height;
  if (p.ConsumeIntegralInRange<int>(0, 3) != 0 && consistent <= (1u << 20)) {
    cloud.row_step = static_cast<std::uint32_t>(row);
    const std::vector<std::uint8_t> bytes = p.ConsumeRemainingBytes<std::uint8_t>();
    cloud.data.resize(consistent);
    for (std::size_t i = 0; !bytes.empty() && i < cloud.data.size(); ++i)
      cloud.data[i] = bytes[i % bytes.size()];
  } else {
    cloud.row_step = count<std::uint32_t>(p, 4096);
    cloud.data = p.ConsumeRemainingBytes<std::uint8_t>();
  }
  try {
    const auto rays = std::make_shared<const sgt::SensorRays>(sgt::makeRays(model));
    const sgt::RangeMeasurements m =
        sgt::ros::measurementsFromCloud(cloud, model, rays, Eigen::Isometry3d::Identity());
    sgt::fuzz::expect(
        m.size() == (sgt::ros::matchesGrid(cloud, model) ? std::size_t(model.columns) * model.rings
                                                         : m.rays->size()),
        "one range per ray: the grid's, or one per point");
    for (std::size_t i = 0; i < m.size(); ++i)
      sgt::fuzz::expect(!m.valid(i) || m.pointInSensor(i).allFinite(), "a finite point per return");
  } catch (const sgt::ros::ConversionError&) {
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzCloud)
