// Latency of the tracker: for every ~tracked_objects message, (receive time - header stamp), the
// header stamp being the depth image's. Run it beside a bag replayed at 1x with --clock (then the
// ROS clock runs at wall speed). Prints p50 / p95 / max on exit (after --duration seconds), and
// when each class first had a confirmed track (seconds after the first message): whether the
// tracker keeps up live, not only how fast it answers.
//   latency_probe [--topic /tracker/tracked_objects] [--duration 25] [--output FILE.json]
#include <ros/ros.h>
#include <scene_graph_tracker/TrackedObjectArray.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

int main(int argc, char** argv) {
  ros::init(argc, argv, "latency_probe", ros::init_options::AnonymousName);
  std::string topic = "/tracker/tracked_objects", output;
  double duration = 25.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--topic")
      topic = argv[i + 1];
    else if (k == "--duration")
      duration = std::stod(argv[i + 1]);
    else if (k == "--output")
      output = argv[i + 1];
  }
  ros::NodeHandle nh;
  std::vector<double> ms;
  ros::Time first;
  std::map<std::string, double> first_confirmed;  // class -> s after the first message
  const auto sub = nh.subscribe<scene_graph_tracker::TrackedObjectArray>(
      topic, 100, [&](const scene_graph_tracker::TrackedObjectArrayConstPtr& m) {
        ms.push_back((ros::Time::now() - m->header.stamp).toSec() * 1000.0);
        if (first.isZero()) first = m->header.stamp;
        for (const auto& o : m->objects)
          if (o.state == scene_graph_tracker::TrackedObject::CONFIRMED)
            first_confirmed.emplace(o.class_name, (m->header.stamp - first).toSec());
      });
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(duration);
  while (ros::ok() && ros::WallTime::now() < end) ros::spinOnce(), ros::WallDuration(0.001).sleep();
  if (ms.empty()) {
    std::cerr << "latency_probe: no messages on " << topic << "\n";
    return 1;
  }
  std::vector<double> s = ms;
  std::sort(s.begin(), s.end());
  const auto q = [&](double p) {
    return s[std::min(s.size() - 1, static_cast<std::size_t>(p * (s.size() - 1) + 0.5))];
  };
  std::ostringstream confirmed;
  const char* sep = "";
  for (const auto& [c, t] : first_confirmed)
    confirmed << sep << "\"" << c << "\": " << t, sep = ", ";
  std::cout << "latency image stamp -> tracked objects: " << s.size() << " messages, p50 " << q(0.5)
            << " ms, p95 " << q(0.95) << " ms, max " << s.back() << " ms; first confirmed (s): {"
            << confirmed.str() << "}\n";
  if (!output.empty())
    std::ofstream(output) << "{\"messages\": " << s.size() << ", \"p50_ms\": " << q(0.5)
                          << ", \"p95_ms\": " << q(0.95) << ", \"max_ms\": " << s.back()
                          << ", \"first_confirmed_s\": {" << confirmed.str() << "}}\n";
  return 0;
}
