# Fuzzing (make fuzz, scripts/fuzz.py). Each target's body, sgtFuzz<Name>() in
# test/fuzz/<name>.cpp (test/fuzz/fuzz_targets.hpp), is built twice:
# - with -DSGT_FUZZ=ON and clang (CC=clang CXX=clang++, a build directory of its own: build/fuzz),
#   as the libFuzzer executable fuzz_<name> (the file then defines LLVMFuzzerTestOneInput);
#   CMakeLists.txt compiles everything there with -fsanitize=fuzzer-no-link,address,undefined,
#   so the libraries the targets link are coverage-instrumented. `cmake --build --target scene_graph_tracker_fuzz`
#   builds the targets and only the libraries they link.
# - with the tests, into test_fuzz_regressions (test/fuzz/test_fuzz_regressions.cpp), which runs
#   every file of test/fuzz/corpus/<name>/ and test/fuzz/regressions/<name>/ through them.

# The targets and the libraries each links.
set(SGT_FUZZ_TARGETS cloud images hypotheses yolo_pose mesh config semap_bridge)
set(SGT_FUZZ_LIBRARIES_cloud ${PROJECT_NAME}_ros)
set(SGT_FUZZ_LIBRARIES_images ${PROJECT_NAME}_ros)
set(SGT_FUZZ_LIBRARIES_hypotheses ${PROJECT_NAME}_ros ${PROJECT_NAME}_simulation)
set(SGT_FUZZ_LIBRARIES_yolo_pose ${PROJECT_NAME}_core)
set(SGT_FUZZ_LIBRARIES_mesh ${PROJECT_NAME}_core)
set(SGT_FUZZ_LIBRARIES_config ${PROJECT_NAME}_simulation yaml-cpp)
set(SGT_FUZZ_LIBRARIES_semap_bridge ${PROJECT_NAME}_semap)

if(SGT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "SGT_FUZZ=ON needs clang (CC=clang CXX=clang++), not ${CMAKE_CXX_COMPILER_ID}")
  endif()
  add_custom_target(${PROJECT_NAME}_fuzz)
  # Developer programs of a build of their own, not installed.
  #catkin_lint: ignore uninstalled_target
  foreach(name ${SGT_FUZZ_TARGETS})
    set(target ${PROJECT_NAME}_fuzz_${name})  # the program: bin/fuzz_<name>
    add_executable(${target} EXCLUDE_FROM_ALL test/fuzz/${name}.cpp)
    target_include_directories(${target} PRIVATE test/fuzz)
    target_compile_definitions(${target} PRIVATE SGT_LIBFUZZER)
    target_link_libraries(${target} ${SGT_FUZZ_LIBRARIES_${name}})
    target_link_options(${target} PRIVATE -fsanitize=fuzzer,address,undefined)
    set_target_properties(${target} PROPERTIES OUTPUT_NAME fuzz_${name} RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
    add_dependencies(${PROJECT_NAME}_fuzz ${target})
  endforeach()
endif()

if(CATKIN_ENABLE_TESTING)
  # The bodies read their bytes with clang's FuzzedDataProvider (header only, libclang-rt-*-dev);
  # gcc gets a copy of it, not clang's include directory (whose intrinsics headers are clang's).
  file(GLOB SGT_FUZZED_DATA_PROVIDER
    /usr/lib/llvm-*/lib/clang/*/include/fuzzer/FuzzedDataProvider.h)
  if(SGT_FUZZED_DATA_PROVIDER)
    list(GET SGT_FUZZED_DATA_PROVIDER -1 fdp)
    #catkin_lint: ignore_once missing_file
    configure_file(${fdp} ${PROJECT_BINARY_DIR}/fuzz_include/fuzzer/FuzzedDataProvider.h COPYONLY)
    set(libraries)
    set(bodies)
    foreach(name ${SGT_FUZZ_TARGETS})
      list(APPEND libraries ${SGT_FUZZ_LIBRARIES_${name}})
      list(APPEND bodies test/fuzz/${name}.cpp)
    endforeach()
    list(REMOVE_DUPLICATES libraries)
    sgt_add_gtests(test/fuzz ${libraries})
    target_sources(${PROJECT_NAME}_test_fuzz_regressions PRIVATE ${bodies})
    target_include_directories(${PROJECT_NAME}_test_fuzz_regressions PRIVATE test/fuzz)
    #catkin_lint: ignore_once missing_directory
    target_include_directories(${PROJECT_NAME}_test_fuzz_regressions SYSTEM PRIVATE ${PROJECT_BINARY_DIR}/fuzz_include)
  else()
    message(WARNING "fuzzer/FuzzedDataProvider.h not found (Debian: libclang-rt-14-dev): "
      "test_fuzz_regressions is not built")
  endif()
endif()
