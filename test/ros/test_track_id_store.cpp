// Track ids are never reused across restarts: the last number per class goes to a file, and a new
// tracker continues after it.
#include <gtest/gtest.h>

#include <fstream>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/ros/track_id_store.hpp"
#include "support.hpp"

namespace sgt::ros {
namespace {

TEST(TrackIdStore, ARestartedPipelineContinuesTheNumbers) {
  const TrackIdStore store(test::tempDir() + "/state/track_ids.yaml");  // directory made on save
  EXPECT_TRUE(store.load().empty()) << "no file yet: nothing was handed out";
  const auto bench = test::benchScene();
  {
    FramePipeline first(bench->catalog, bench->map);
    for (int i = 0; i < 3; ++i) first.addTrack("klt", bench->truth[3], 0.0);
    first.addTrack("relay", bench->truth[4], 0.0);
    store.save(first.lastTrackNumbers());
  }
  EXPECT_EQ(store.load(), (std::map<std::string, int>{{"klt", 3}, {"relay", 1}}));
  FramePipeline second(bench->catalog, bench->map);
  second.continueTrackNumbers(store.load());
  EXPECT_EQ(second.addTrack("klt", bench->truth[3], 0.0), "klt_4");
  EXPECT_EQ(second.addTrack("multimeter", bench->truth[0], 0.0), "multimeter_1");
  second.continueTrackNumbers({{"klt", 2}});  // never backwards
  EXPECT_EQ(second.addTrack("klt", bench->truth[3], 0.0), "klt_5");
}

TEST(TrackIdStore, AMalformedFileIsAnErrorNotASilentRestartAtOne) {
  for (const char* text : {"[1, 2]", "klt: -1", "klt: many", "klt: [3]", "{klt: 3"}) {
    const std::string path = test::writeFile("ids.yaml", text);
    EXPECT_THROW(TrackIdStore(path).load(), TrackIdStoreError) << text;
  }
  EXPECT_TRUE(TrackIdStore(test::writeFile("empty.yaml", "")).load().empty());
  EXPECT_FALSE(TrackIdStore("").enabled());
  EXPECT_THROW(TrackIdStore("/proc/sgt_no_such_dir/ids.yaml").save({{"klt", 1}}),
               TrackIdStoreError);
}

}  // namespace
}  // namespace sgt::ros
