// The libFuzzer targets' bodies (test/fuzz/<name>.cpp), shared by the fuzzers (make fuzz,
// cmake/fuzz.cmake: built with clang and -DSGT_LIBFUZZER, where each file also defines
// LLVMFuzzerTestOneInput) and the gcc build's test_fuzz_regressions, which runs every file of
// test/fuzz/corpus/<name>/ and test/fuzz/regressions/<name>/ through them.
//
// Each body builds its inputs from the bytes and calls the code under test; the errors that code
// documents (ConversionError, MeshError, ...) are caught, anything else (a crash, a sanitizer
// report, an uncaught exception, a timeout or an out-of-memory) is a finding. Always returns 0.
#pragma once

#include <cstddef>
#include <cstdint>

int sgtFuzzCloud(const std::uint8_t* data, std::size_t size);        // rangesFromCloud
int sgtFuzzImages(const std::uint8_t* data, std::size_t size);       // CameraInfo, depth, RGB
int sgtFuzzHypotheses(const std::uint8_t* data, std::size_t size);   // hypotheses -> pipeline
int sgtFuzzYoloPose(const std::uint8_t* data, std::size_t size);     // decodeYoloPose
int sgtFuzzMesh(const std::uint8_t* data, std::size_t size);         // loadMesh
int sgtFuzzConfig(const std::uint8_t* data, std::size_t size);       // catalog, scenario, URDF
int sgtFuzzSemapBridge(const std::uint8_t* data, std::size_t size);  // scene graph -> rows

#ifdef SGT_LIBFUZZER
#define SGT_FUZZ_ENTRY(body)                                                          \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    return body(data, size);                                                          \
  }
#else
#define SGT_FUZZ_ENTRY(body)
#endif
