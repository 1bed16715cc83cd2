// Under ThreadSanitizer (make test-tsan) TBB runs every parallel loop on its calling thread.
// libtbb is not instrumented: TSan cannot see the synchronisation of TBB's task hand-off and
// would report the writes of every parallel loop (ours and Embree's BVH builds) as races, and its
// spinning workers make the suite hours long. The package's own threads (ROS callbacks, the image
// receiver, the SEMAP writer) stay under TSan. In any other build this file is empty.
#if defined(__SANITIZE_THREAD__)
#include <tbb/global_control.h>

namespace sgt {
namespace {

const tbb::global_control kSerialTbb(tbb::global_control::max_allowed_parallelism, 1);

}  // namespace
}  // namespace sgt
#endif
