#include "scene_graph_tracker/evaluation/report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

#include "scene_graph_tracker/evaluation/json_number.hpp"

namespace sgt {
namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(pos);
  const double frac = pos - i;
  return i + 1 < v.size() ? v[i] * (1 - frac) + v[i + 1] * frac : v[i];
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

struct ObjectStats {
  std::vector<double> add_s, add, t, r, add_or_adds;
  std::vector<double> depth_mm, gt_depth_mm;  // surface fits, where measured
  std::vector<double> alone_mm, excess_mm;    // the mesh fitted alone; tracked minus that
  std::size_t evaluated = 0, correct = 0, missed = 0, out_of_view = 0, correct_add_or_adds = 0;
  std::size_t displaced = 0, turned = 0;  // wrong ADD(-S): a wrong place, or a wrong turn only
  std::size_t crossed = 0;                // of the displaced: on another object of the class
  void add_row(const std::optional<PoseErrors>& e, bool in_view) {
    if (!in_view) {
      ++out_of_view;
      return;
    }
    ++evaluated;
    if (!e) {
      ++missed;
      return;
    }
    add_s.push_back(e->add_s * 1000), add.push_back(e->add * 1000);
    t.push_back(e->translation * 1000), r.push_back(e->rotation_deg);
    add_or_adds.push_back(e->add_or_adds * 1000);
    correct += e->correct, correct_add_or_adds += e->correct_add_or_adds;
    if (!e->correct_add_or_adds) ++(e->displaced ? displaced : turned);
    crossed += !e->correct_add_or_adds && e->displaced && e->crossed;
  }
  void addFit(const std::optional<double>& tracked_m, const std::optional<double>& given_m,
              const std::optional<double>& alone_m) {
    if (tracked_m) depth_mm.push_back(*tracked_m * 1000);
    if (given_m) gt_depth_mm.push_back(*given_m * 1000);
    if (alone_m) alone_mm.push_back(*alone_m * 1000);
    if (tracked_m && alone_m) excess_mm.push_back((*tracked_m - *alone_m) * 1000);
  }
  double recall() const { return evaluated ? static_cast<double>(correct) / evaluated : 0.0; }
  double recallAddOrAdds() const {
    return evaluated ? static_cast<double>(correct_add_or_adds) / evaluated : 0.0;
  }
  std::string json(const std::string& indent) const {
    std::ostringstream o;
    o << indent << "\"evaluated\": " << evaluated << ",\n"
      << indent << "\"missed\": " << missed << ",\n"
      << indent << "\"out_of_view\": " << out_of_view << ",\n"
      << indent << "\"displaced\": " << displaced << ",\n"
      << indent << "\"turned\": " << turned << ",\n"
      << indent << "\"crossed\": " << crossed << ",\n"
      << indent << "\"add_s_mean_mm\": " << jsonNumber(mean(add_s)) << ",\n"
      << indent << "\"add_mean_mm\": " << jsonNumber(mean(add)) << ",\n"
      << indent << "\"recall_adds_10\": " << jsonNumber(recall()) << ",\n"
      << indent << "\"translation_error_mean_mm\": " << jsonNumber(mean(t)) << ",\n"
      << indent << "\"rotation_error_mean_deg\": " << jsonNumber(mean(r)) << ",\n"
      << indent << "\"add_or_adds_mean_mm\": " << jsonNumber(mean(add_or_adds)) << ",\n"
      << indent << "\"recall_add_or_adds_10\": " << jsonNumber(recallAddOrAdds());
    if (!depth_mm.empty() || !gt_depth_mm.empty())
      o << ",\n"
        << indent << "\"depth_residual_median_mm\": "
        << jsonNumber(depth_mm.empty() ? NAN : quantile(depth_mm, 0.5)) << ",\n"
        << indent << "\"gt_depth_residual_median_mm\": "
        << jsonNumber(gt_depth_mm.empty() ? NAN : quantile(gt_depth_mm, 0.5));
    if (!alone_mm.empty())
      o << ",\n"
        << indent << "\"depth_residual_alone_median_mm\": " << jsonNumber(quantile(alone_mm, 0.5))
        << ",\n"
        << indent << "\"depth_residual_excess_max_mm\": "
        << jsonNumber(excess_mm.empty() ? NAN
                                        : *std::max_element(excess_mm.begin(), excess_mm.end()));
    return o.str();
  }
};

}  // namespace

void EvaluationReport::addFrame(double stamp, const StageTimes& times) {
  frames_.push_back({stamp, times, {}, {}});
}

void EvaluationReport::addObject(double stamp, const std::string& id, const std::string& cls,
                                 const std::string& track, const std::optional<PoseErrors>& e,
                                 bool in_view) {
  objects_.push_back({stamp, id, cls, e, in_view, track, std::nullopt, std::nullopt, std::nullopt});
  if (!in_view) return;
  if (track.empty()) return;
  std::string& last = last_track_[id];
  if (!last.empty() && last != track) ++switches_[id];
  last = track;
}

void EvaluationReport::addSurfaceFit(double stamp, const std::string& truth_id,
                                     std::optional<double> tracked_m, std::optional<double> given_m,
                                     std::optional<double> alone_m) {
  for (auto r = objects_.rbegin(); r != objects_.rend() && r->stamp == stamp; ++r)
    if (r->id == truth_id) {
      r->depth_residual_m = tracked_m, r->gt_depth_residual_m = given_m;
      r->alone_depth_residual_m = alone_m;
      return;
    }
}

void EvaluationReport::addFalsePositive(double stamp, const std::string& track_id,
                                        const std::string& class_name) {
  false_positives_.push_back({stamp, track_id, class_name});
}

std::string EvaluationReport::falsePositivesJson() const {
  std::set<std::string> tracks;
  std::map<std::string, std::size_t> by_class;
  for (const FalsePositiveRow& f : false_positives_)
    tracks.insert(f.track_id), ++by_class[f.class_name];
  std::ostringstream o;
  o << ",\n    \"false_positives\": " << false_positives_.size()
    << ",\n    \"false_tracks\": " << tracks.size() << ",\n    \"false_positives_by_class\": {";
  bool first = true;
  for (const auto& [c, n] : by_class)
    o << (first ? "" : ", ") << "\"" << c << "\": " << n, first = false;
  o << "}";
  return o.str();
}

void EvaluationReport::addHypothesis(const std::string& truth_id,
                                     const std::optional<PoseErrors>& nearest,
                                     double box_turn_deg) {
  HypothesisCounts& c = hypotheses_[truth_id];
  ++c.evaluated;
  if (!nearest) return;
  ++c.found;
  c.t_mm.push_back(nearest->translation * 1000), c.r_deg.push_back(nearest->rotation_deg);
  if (std::isfinite(box_turn_deg)) c.r_box_deg.push_back(box_turn_deg);
}

std::string EvaluationReport::hypothesesJson() const {
  if (hypotheses_.empty()) return "";
  const auto fields = [](const HypothesisCounts& c, const std::string& indent) {
    std::ostringstream o;
    o << indent << "\"evaluated\": " << c.evaluated << ",\n"
      << indent << "\"found\": " << c.found << ",\n"
      << indent << "\"recall\": "
      << jsonNumber(c.evaluated ? static_cast<double>(c.found) / c.evaluated : NAN) << ",\n"
      << indent << "\"translation_error_median_mm\": "
      << jsonNumber(c.t_mm.empty() ? NAN : quantile(c.t_mm, 0.5)) << ",\n"
      << indent << "\"rotation_error_median_deg\": "
      << jsonNumber(c.r_deg.empty() ? NAN : quantile(c.r_deg, 0.5)) << ",\n"
      << indent << "\"rotation_error_up_to_box_turns_median_deg\": "
      << jsonNumber(c.r_box_deg.empty() ? NAN : quantile(c.r_box_deg, 0.5));
    return o.str();
  };
  HypothesisCounts all;
  for (const auto& [id, c] : hypotheses_) {
    all.evaluated += c.evaluated, all.found += c.found;
    all.t_mm.insert(all.t_mm.end(), c.t_mm.begin(), c.t_mm.end());
    all.r_deg.insert(all.r_deg.end(), c.r_deg.begin(), c.r_deg.end());
    all.r_box_deg.insert(all.r_box_deg.end(), c.r_box_deg.begin(), c.r_box_deg.end());
  }
  std::ostringstream o;
  o << "  \"hypotheses\": {\n" << fields(all, "    ") << ",\n    \"per_object\": {";
  bool first = true;
  for (const auto& [id, c] : hypotheses_)
    o << (first ? "\n" : ",\n") << "      \"" << id << "\": {\n"
      << fields(c, "        ") << "\n      }",
        first = false;
  o << "\n    }\n  },\n";
  return o.str();
}

std::string EvaluationReport::hypothesesMarkdown() const {
  if (hypotheses_.empty()) return "";
  std::ostringstream o;
  o << std::fixed << "\nPose hypotheses (nearest of the class within the gate, true base pose):\n\n"
    << "| object | frames in view | with a hypothesis | share | t mm median | R deg median | "
       "R deg up to box turns |\n|---|---|---|---|---|---|---|\n";
  const auto median = [](const std::vector<double>& v) {
    std::ostringstream m;
    m << std::fixed << std::setprecision(1);
    if (v.empty())
      m << "–";  // no hypothesis came within the gate
    else
      m << quantile(v, 0.5);
    return m.str();
  };
  for (const auto& [id, c] : hypotheses_)
    o << "| " << id << " | " << c.evaluated << " | " << c.found << " | " << std::setprecision(3)
      << (c.evaluated ? static_cast<double>(c.found) / c.evaluated : 0.0) << " | " << median(c.t_mm)
      << " | " << median(c.r_deg) << " | " << median(c.r_box_deg) << " |\n";
  return o.str();
}

void EvaluationReport::addLocalization(double stamp, double t, double r) {
  if (!frames_.empty() && frames_.back().stamp == stamp) {
    frames_.back().loc_t = t;
    frames_.back().loc_r = r;
  }
}

void EvaluationReport::addPresegmentation(const UnknownLabelCounts& c) {
  labels_.tp += c.tp, labels_.fp += c.fp, labels_.fn += c.fn;
  labels_.lidar_valid += c.lidar_valid, labels_.lidar_unknown += c.lidar_unknown;
}

void EvaluationReport::addRelations(const RelationCounts& c, std::size_t declared) {
  relations_ += c;
  ++relation_frames_;
  declared_relations_ = declared;
}

std::string EvaluationReport::json() const {
  ObjectStats all;
  std::map<std::string, ObjectStats> per;
  std::map<std::string, std::string> cls;
  for (const ObjectRow& r : objects_) {
    all.add_row(r.e, r.in_view), per[r.id].add_row(r.e, r.in_view), cls[r.id] = r.class_name;
    all.addFit(r.depth_residual_m, r.gt_depth_residual_m, r.alone_depth_residual_m);
    per[r.id].addFit(r.depth_residual_m, r.gt_depth_residual_m, r.alone_depth_residual_m);
  }
  std::vector<double> lt, lr, total, loc, refine, preseg, detect, relations;
  for (const FrameRow& f : frames_) {
    if (f.loc_t) lt.push_back(*f.loc_t * 1000), lr.push_back(*f.loc_r);
    total.push_back(f.times.total_ms);
    if (f.times.detect_ms > 0) detect.push_back(f.times.detect_ms);
    if (f.times.localize_ms > 0.05)
      loc.push_back(f.times.localize_ms);  // frames that localized (with a scan)
    refine.push_back(f.times.refine_ms), preseg.push_back(f.times.presegment_ms);
    relations.push_back(f.times.relations_ms);
  }
  const auto ratio = [](std::size_t a, std::size_t b) {
    return b ? static_cast<double>(a) / b : NAN;
  };
  std::ostringstream o;
  int switches = 0;
  for (const auto& [id, n] : switches_) switches += n;
  o << "{\n  \"frames\": " << frames_.size() << ",\n  \"objects\": {\n"
    << all.json("    ") << ",\n    \"identity_switches\": " << switches << falsePositivesJson()
    << ",\n    \"per_object\": {";
  bool first = true;
  for (const auto& [id, s] : per) {
    const auto sw = switches_.find(id);
    o << (first ? "\n" : ",\n") << "      \"" << id << "\": {\n        \"class\": \"" << cls[id]
      << "\",\n"
      << "        \"identity_switches\": " << (sw == switches_.end() ? 0 : sw->second) << ",\n"
      << s.json("        ") << "\n      }";
    first = false;
  }
  o << "\n    }\n  },\n"
    << hypothesesJson() << "  \"localization\": {\n    \"frames\": " << lt.size()
    << ",\n    \"translation_error_mean_mm\": " << jsonNumber(mean(lt))
    << ",\n    \"rotation_error_mean_deg\": " << jsonNumber(mean(lr))
    << ",\n    \"translation_error_max_mm\": "
    << jsonNumber(lt.empty() ? NAN : *std::max_element(lt.begin(), lt.end())) << "\n  },\n"
    << "  \"presegmentation\": {\n    \"reduction\": "
    << jsonNumber(labels_.lidar_valid
                      ? 1.0 - static_cast<double>(labels_.lidar_unknown) / labels_.lidar_valid
                      : NAN)
    << ",\n    \"precision\": " << jsonNumber(ratio(labels_.tp, labels_.tp + labels_.fp))
    << ",\n    \"recall\": " << jsonNumber(ratio(labels_.tp, labels_.tp + labels_.fn))
    << ",\n    \"lidar_valid_points\": " << labels_.lidar_valid
    << ",\n    \"lidar_unknown_points\": " << labels_.lidar_unknown << "\n  },\n"
    << "  \"sensors\": {\n    \"depth_sigma_at_1m_median\": "
    << jsonNumber(depth_sigma_at_1m_.empty() ? NAN : quantile(depth_sigma_at_1m_, 0.5))
    << "\n  },\n";
  if (relation_frames_ > 0)
    o << "  \"relations\": {\n    \"precision\": "
      << jsonNumber(ratio(relations_.tp, relations_.tp + relations_.fp))
      << ",\n    \"recall\": " << jsonNumber(ratio(relations_.tp, relations_.tp + relations_.fn))
      << ",\n    \"true_positives\": " << relations_.tp
      << ",\n    \"false_positives\": " << relations_.fp
      << ",\n    \"false_negatives\": " << relations_.fn
      << ",\n    \"frames\": " << relation_frames_ << ",\n    \"declared\": " << declared_relations_
      << "\n  },\n";
  o << tracks_.json("  ") << ",\n";
  o << "  \"timing\": {\n    \"frame_ms_median\": " << jsonNumber(quantile(total, 0.5))
    << ",\n    \"frame_ms_p95\": " << jsonNumber(quantile(total, 0.95))
    << ",\n    \"localize_ms_median\": " << jsonNumber(quantile(loc, 0.5))
    << ",\n    \"refine_ms_median\": " << jsonNumber(quantile(refine, 0.5))
    << ",\n    \"presegment_ms_median\": " << jsonNumber(quantile(preseg, 0.5))
    << ",\n    \"relations_ms_median\": " << jsonNumber(quantile(relations, 0.5))
    << ",\n    \"detect_ms_median\": " << jsonNumber(quantile(detect, 0.5)) << "\n  }\n}\n";
  return o.str();
}

std::string EvaluationReport::markdown() const {
  std::map<std::string, ObjectStats> per;
  std::map<std::string, std::string> cls;
  ObjectStats all;
  for (const ObjectRow& r : objects_)
    all.add_row(r.e, r.in_view), per[r.id].add_row(r.e, r.in_view), cls[r.id] = r.class_name;
  std::ostringstream o;
  o << std::fixed << std::setprecision(2);
  o << "| object | class | frames | missed | out of view | ADD-S mm | ADD mm | t mm | R deg | "
       "recall ADD-S<0.1d | ADD(-S) mm | recall ADD(-S)<0.1d |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  const auto row = [&](const std::string& id, const std::string& c, const ObjectStats& s) {
    o << "| " << id << " | " << c << " | " << s.evaluated << " | " << s.missed << " | "
      << s.out_of_view << " | " << mean(s.add_s) << " | " << mean(s.add) << " | " << mean(s.t)
      << " | " << mean(s.r) << " | " << std::setprecision(3) << s.recall() << std::setprecision(2)
      << " | " << mean(s.add_or_adds) << " | " << std::setprecision(3) << s.recallAddOrAdds()
      << std::setprecision(2) << " |\n";  // the goal is 0.99: 3 digits
  };
  for (const auto& [id, s] : per) row(id, cls[id], s);
  row("**all**", "", all);
  if (!false_positives_.empty()) {
    std::map<std::string, std::set<std::string>> tracks;
    for (const FalsePositiveRow& f : false_positives_) tracks[f.class_name].insert(f.track_id);
    o << "\nFalse positives (tracks in the scene graph matched to no object): "
      << false_positives_.size() << " track-frames of";
    const char* sep = " ";
    for (const auto& [c, ids] : tracks)
      o << sep << ids.size() << " " << c << (ids.size() == 1 ? " track" : " tracks"), sep = ", ";
    o << ".\n";
  }
  o << surfaceMarkdown() << tracks_.markdown();
  o << hypothesesMarkdown();
  std::vector<double> lt, lr, total;
  for (const FrameRow& f : frames_) {
    if (f.loc_t) lt.push_back(*f.loc_t * 1000), lr.push_back(*f.loc_r);
    total.push_back(f.times.total_ms);
  }
  o << "\n| localization t mm | R deg | pre-seg. reduction | precision | recall | frame ms median "
       "| p95 |\n"
    << "|---|---|---|---|---|---|---|\n| " << mean(lt) << " | " << std::setprecision(3) << mean(lr)
    << " | "
    << (labels_.lidar_valid ? 1.0 - static_cast<double>(labels_.lidar_unknown) / labels_.lidar_valid
                            : 0.0)
    << " | "
    << (labels_.tp + labels_.fp ? static_cast<double>(labels_.tp) / (labels_.tp + labels_.fp) : 0.0)
    << " | "
    << (labels_.tp + labels_.fn ? static_cast<double>(labels_.tp) / (labels_.tp + labels_.fn) : 0.0)
    << " | " << std::setprecision(1) << quantile(total, 0.5) << " | " << quantile(total, 0.95)
    << " |\n";
  if (relation_frames_ > 0) {
    const auto share = [](std::size_t a, std::size_t b) {
      return b ? static_cast<double>(a) / b : 0.0;
    };
    o << "\n| relations precision | recall | tp | fp | fn |\n|---|---|---|---|---|\n| "
      << std::setprecision(3) << share(relations_.tp, relations_.tp + relations_.fp) << " | "
      << share(relations_.tp, relations_.tp + relations_.fn) << " | " << relations_.tp << " | "
      << relations_.fp << " | " << relations_.fn << " |\n";
  }
  return o.str();
}

std::string EvaluationReport::surfaceMarkdown() const {
  std::map<std::string, ObjectStats> per;
  for (const ObjectRow& r : objects_)
    per[r.id].addFit(r.depth_residual_m, r.gt_depth_residual_m, r.alone_depth_residual_m);
  std::ostringstream o;
  o << std::fixed << std::setprecision(2);
  bool any = false;
  for (const auto& [id, s] : per) {
    if (s.depth_mm.empty() && s.gt_depth_mm.empty()) continue;
    if (!any)
      o << "\nDepth residual on the visible surface, median over frames (mm):\n\n"
           "| object | tracked pose | given pose | frames fitted |\n|---|---|---|---|\n";
    any = true;
    const auto med = [](const std::vector<double>& v) {
      return v.empty() ? std::string("–") : jsonNumber(std::round(quantile(v, 0.5) * 100) / 100);
    };
    o << "| " << id << " | " << med(s.depth_mm) << " | " << med(s.gt_depth_mm) << " | "
      << s.depth_mm.size() << " |\n";
  }
  return o.str();
}

std::string EvaluationReport::timeseriesCsv() const {
  std::ostringstream o;
  o << std::setprecision(15);  // stamps are ~1.7e9 s: keep the milliseconds
  o << "kind,stamp,id,class,add_s_mm,add_mm,t_mm,r_deg,localize_ms,associate_ms,refine_ms,"
       "presegment_ms,total_ms,"
       "loc_t_mm,loc_r_deg,track,depth_residual_mm,gt_depth_residual_mm,inliers,inlier_ratio,"
       "confirmed,in_view,x,y,z,qx,qy,qz,qw,alone_depth_residual_mm,orientation_confidence\n";
  const char* no_pose = ",,,,,,,,,";  // pose, alone residual, confidence
  for (const ObjectRow& r : objects_)
    o << "object," << r.stamp << "," << r.id << "," << r.class_name << ","
      << (r.e ? jsonNumber(r.e->add_s * 1000) : "") << ","
      << (r.e ? jsonNumber(r.e->add * 1000) : "") << ","
      << (r.e ? jsonNumber(r.e->translation * 1000) : "") << ","
      << (r.e ? jsonNumber(r.e->rotation_deg) : "") << ",,,,,,,," << r.track << ","
      << (r.depth_residual_m ? jsonNumber(*r.depth_residual_m * 1000) : "") << ","
      << (r.gt_depth_residual_m ? jsonNumber(*r.gt_depth_residual_m * 1000) : "") << ",,,,"
      << (r.in_view ? 1 : 0) << ",,,,,,,,"
      << (r.alone_depth_residual_m ? jsonNumber(*r.alone_depth_residual_m * 1000) : "") << ",\n";
  for (const FalsePositiveRow& f : false_positives_)
    o << "false_positive," << f.stamp << "," << f.track_id << "," << f.class_name << ",,,,,,,,,,,,"
      << f.track_id << ",,,,,," << no_pose << "\n";
  for (const FrameRow& f : frames_)
    o << "frame," << f.stamp << ",,,,,,," << f.times.localize_ms << "," << f.times.associate_ms
      << "," << f.times.refine_ms << "," << f.times.presegment_ms << "," << f.times.total_ms << ","
      << (f.loc_t ? jsonNumber(*f.loc_t * 1000) : "") << ","
      << (f.loc_r ? jsonNumber(*f.loc_r) : "") << ",,,,,,," << no_pose << "\n";
  o << tracks_.csvRows();
  return o.str();
}

}  // namespace sgt
