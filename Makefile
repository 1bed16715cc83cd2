# scene_graph_tracker — developer entry points. See README.md.
SHELL := /bin/bash
export PATH := /usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
BUILD ?= build
JOBS ?= 2
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DCATKIN_DEVEL_PREFIX=$(CURDIR)/$(BUILD)/devel

.PHONY: deps build test test-asan test-tsan install-check bench demo suite ablation real latency soak model photos params fuzz clean

deps:
	@scripts/install-deps.sh

# Order-only on deps: under make -j the configure step must not start before the packages it
# finds are installed. A failed configure leaves no cache behind, so the next make retries it.
$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS) || { rm -f $@; exit 1; }

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j$(JOBS)

test: build
	@rm -rf $(BUILD)/test_results $(SAN_LOGS)
	$(SAN_SETUP)
	$(SAN_ENV) cmake --build $(BUILD) -j$(JOBS) --target tests
	-@SGT_REQUIRE_DB=1 $(SAN_ENV) cmake --build $(BUILD) --target run_tests -- -k > $(BUILD)/run_tests.log 2>&1; true
	@/usr/bin/python3 scripts/test_summary.py $(BUILD)/test_results $(BUILD)/run_tests.log \
	  $(if $(SANITIZER),--sanitizer-logs $(SAN_LOGS))

# make test in a sanitized build of its own: test-asan (AddressSanitizer + UndefinedBehaviorSanitizer,
# $(BUILD)/asan), test-tsan (ThreadSanitizer, $(BUILD)/tsan); gcc, -O1 -g. Every sanitizer report
# fails the run, even when its test passed: the sanitized processes write them to
# $(BUILD)/<kind>/sanitizer/, test_summary.py prints them and counts the failed case "sanitizer
# reports". Suppressions (third-party code only, each with its reason): test/sanitizers/*.supp.
# The nodelet manager (/usr/lib/nodelet/nodelet, not instrumented) loads our instrumented nodelet
# library: the rostests start it through test/sanitizers/nodelet, which preloads the runtime.
SAN_CXX_FLAGS_asan := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
SAN_CXX_FLAGS_tsan := -fsanitize=thread
# UBSan's reports to its log_path too, not stderr (test/sanitizers/ubsan_log_path.cpp says why).
SAN_LINK_OBJECT_asan := $(CURDIR)/$(BUILD)/asan/ubsan_log_path.o
san_cmake_flags = -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="$(SAN_CXX_FLAGS_$(1))" -DCATKIN_DEVEL_PREFIX=$(CURDIR)/$(BUILD)/$(1)/devel \
  -DCMAKE_EXE_LINKER_FLAGS="$(SAN_LINK_OBJECT_$(1))" -DCMAKE_SHARED_LINKER_FLAGS="$(SAN_LINK_OBJECT_$(1))"
test-asan test-tsan: test-%:
	@mkdir -p $(BUILD)/$*
	$(if $(SAN_LINK_OBJECT_$*),g++ -O1 -g -fPIC -c test/sanitizers/ubsan_log_path.cpp -o $(SAN_LINK_OBJECT_$*))
	@$(MAKE) --no-print-directory test SANITIZER=$* BUILD=$(BUILD)/$* CMAKE_FLAGS='$(call san_cmake_flags,$*)'

SANITIZER ?=
SAN_LOGS := $(if $(SANITIZER),$(CURDIR)/$(BUILD)/sanitizer)
SAN_SUPP := $(CURDIR)/test/sanitizers
SAN_RUNTIME_asan = $(shell gcc -print-file-name=libasan.so)
SAN_RUNTIME_tsan = $(shell gcc -print-file-name=libtsan.so)
SAN_OPTIONS_asan = ASAN_OPTIONS=log_path=$(SAN_LOGS)/asan:log_exe_name=1:detect_stack_use_after_return=1:check_initialization_order=1 \
  UBSAN_OPTIONS=log_path=$(SAN_LOGS)/ubsan:log_exe_name=1:print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions=$(SAN_SUPP)/lsan.supp:print_suppressions=0
SAN_OPTIONS_tsan = TSAN_OPTIONS=log_path=$(SAN_LOGS)/tsan:log_exe_name=1:halt_on_error=0:second_deadlock_stack=1:suppressions=$(SAN_SUPP)/tsan.supp:print_suppressions=0
SAN_ENV := $(if $(SANITIZER),$(SAN_OPTIONS_$(SANITIZER)) SGT_SANITIZER_RUNTIME=$(SAN_RUNTIME_$(SANITIZER)))
SAN_SETUP := $(if $(SANITIZER),@mkdir -p $(SAN_LOGS) $(BUILD)/devel/lib/nodelet && \
  ln -sf $(SAN_SUPP)/nodelet $(BUILD)/devel/lib/nodelet/nodelet)

# The package as an install space with the source tree hidden (scripts/install-check.sh); also
# part of make test.
install-check: build
	cmake --build $(BUILD) -j$(JOBS) --target scene_graph_tracker_rostest_tracker
	@scripts/install-check.sh $(BUILD)

bench: build
	cmake --build $(BUILD) -j$(JOBS) --target scene_graph_tracker_benchmarks
	@scripts/run-benchmarks.sh $(BUILD)

# Simulate the default scenario into a bag and write its static world beside it (write_map: the
# simulated building as a mesh and its workbench top as furniture, what replay.launch passes to the
# tracker), then replay the bag through the pipeline on that map and score it.
DEMO_DIR ?= $(BUILD)/demo
DEMO_SCENARIO ?= config/scenarios/workbench.yaml
# Hypotheses from the package's keypoint detector on the RGB images (models/sgt_keypoints.yaml);
# `make demo DEMO_DETECTOR=` uses the bag's simulated hypotheses instead (refinement alone).
DEMO_DETECTOR ?= default
TOOLS := $(BUILD)/devel/lib/scene_graph_tracker
demo: build
	@mkdir -p $(DEMO_DIR)
	$(TOOLS)/simulate --scenario $(DEMO_SCENARIO) --output $(DEMO_DIR)/workbench.bag $(DEMO_SIMULATE_ARGS)
	$(TOOLS)/write_map --scenario $(DEMO_SCENARIO) --mesh $(DEMO_DIR)/static_map.ply --furniture $(DEMO_DIR)/furniture.yaml
	$(TOOLS)/evaluate --bag $(DEMO_DIR)/workbench.bag --output $(DEMO_DIR) --scenario $(DEMO_SCENARIO) \
	  --map $(DEMO_DIR)/static_map.ply --furniture $(DEMO_DIR)/furniture.yaml \
	  $(if $(DEMO_DETECTOR),--detector $(DEMO_DETECTOR)) $(DEMO_EVALUATE_ARGS)

# The scenario suite: SUITE_COUNT generated scenarios (generate_scenarios --seed SUITE_SEED), each
# simulated, scored (its bag deleted once scored), SUITE_JOBS at a time; summary in SUITE_DIR
# (summary.json, summary.md, recall.png). SUITE_DETECTOR= scores the simulated hypotheses,
# SUITE_DETECTOR=default the package's detector; SUITE_MESH_DIR= the package's meshes, or e.g.
# ../shared/data/pbr_objects/meshes. SUITE_ARGS=--keep-bags keeps the bags (1.6 GB each) and
# replays them on the next such run instead of simulating again.
SUITE_COUNT ?= 20
SUITE_SEED ?= 1
SUITE_DETECTOR ?=
SUITE_MESH_DIR ?=
SUITE_JOBS ?= 2
SUITE_DIR ?= $(BUILD)/suite
suite: build
	@/usr/bin/python3 scripts/suite.py --tools $(TOOLS) --output $(SUITE_DIR) --count $(SUITE_COUNT) \
	  --seed $(SUITE_SEED) --jobs $(SUITE_JOBS) $(if $(SUITE_DETECTOR),--detector $(SUITE_DETECTOR)) \
	  $(if $(SUITE_MESH_DIR),--mesh-dir $(SUITE_MESH_DIR)) $(SUITE_ARGS)

# Tracker rules judged on the suite: the suite (SUITE_COUNT, SUITE_SEED, SUITE_DETECTOR,
# SUITE_MESH_DIR, SUITE_JOBS) once with the package's parameters, keeping its bags, then once per
# variant of config/ablation.yaml (each rule switched off, each candidate on), replaying those
# bags. ABLATION_VARIANTS=a,b runs only those; variants already scored are read, not run again.
# Writes ABLATION_DIR/ablation.md (the table against the baseline) and ablation.json.
ABLATION_DIR ?= $(BUILD)/ablation
ABLATION_VARIANTS ?=
ablation: build
	@/usr/bin/python3 scripts/ablation.py --tools $(TOOLS) --output $(ABLATION_DIR) --count $(SUITE_COUNT) \
	  --seed $(SUITE_SEED) --jobs $(SUITE_JOBS) $(if $(SUITE_DETECTOR),--detector $(SUITE_DETECTOR)) \
	  $(if $(SUITE_MESH_DIR),--mesh-dir $(SUITE_MESH_DIR)) $(if $(ABLATION_VARIANTS),--only $(ABLATION_VARIANTS))

# A real RGB-D recording (a sequence folder: evaluation/rgbd_sequence.hpp) as a bag
# (sequence_to_bag), then scored with the camera only: the recording's camera poses as an external
# localization, no LiDAR, and as the static map only the plane the objects stand on (the largest
# plane of the first frame's depth). REAL_DETECTOR= starts tracks from the given poses plus the simulated detector's noise;
# a model yaml from the package's keypoint detector instead. Writes REAL_OUTPUT/report.json
# (objects.depth_residual_median_mm and gt_depth_residual_median_mm too), report.md, plots, the
# overlay frames REAL_OUTPUT/overlay/ and their contact sheet REAL_OUTPUT/overlay.jpg. With a
# REAL_DETECTOR, the detector alone is also scored on the frames labelled from the given poses
# (sequence_to_dataset, evaluate_detector): REAL_OUTPUT/detector/report.json.
REAL_SEQUENCE ?= ../shared/data/real/visp_rbt
REAL_CATALOG ?= config/real/visp_rbt.yaml
REAL_DETECTOR ?=
REAL_OUTPUT ?= $(BUILD)/real
REAL_SEED ?= 1
# The labels the detector alone is scored against (sequence_to_dataset --labels): the model's own kind
REAL_LABELS ?= object
real: build
	@test -d $(REAL_SEQUENCE) || { echo "make real: no sequence at $(REAL_SEQUENCE) (REAL_SEQUENCE=DIR)"; exit 1; }
	@mkdir -p $(REAL_OUTPUT)
	$(TOOLS)/sequence_to_bag --sequence $(REAL_SEQUENCE) --output $(REAL_OUTPUT)/sequence.bag --seed $(REAL_SEED) \
	  --plane-map $(REAL_OUTPUT)/plane.ply
	$(TOOLS)/evaluate --bag $(REAL_OUTPUT)/sequence.bag --output $(REAL_OUTPUT) --catalog $(REAL_CATALOG) \
	  --mesh-dir $(REAL_SEQUENCE)/models --map $(REAL_OUTPUT)/plane.ply --fit-alone \
	  --odom-frame map --base-frame camera_color_optical_frame --localization external --no-relations --overlay \
	  $(if $(REAL_DETECTOR),--detector $(REAL_DETECTOR)) $(REAL_EVALUATE_ARGS)
	$(if $(REAL_DETECTOR),$(TOOLS)/sequence_to_dataset --sequence $(REAL_SEQUENCE) --catalog $(REAL_CATALOG) \
	  --mesh-dir $(REAL_SEQUENCE)/models --output $(REAL_OUTPUT)/frames --labels $(REAL_LABELS) && \
	  $(TOOLS)/evaluate_detector --dataset $(REAL_OUTPUT)/frames --model $(REAL_DETECTOR) --catalog $(REAL_CATALOG) \
	  --mesh-dir $(REAL_SEQUENCE)/models --output $(REAL_OUTPUT)/detector)

# The demo bag in a loop at SOAK_RATE x through tracker + detector + semap_bridge on a roscore of
# its own for SOAK_MINUTES; RSS, descriptors, threads, counters and database size every 10 s, in
# $(BUILD)/soak/soak.json (scripts/soak.py). Fails on a crash, RSS growth >= 5 % after 2 min, or
# database rows that differ from the rows written.
SOAK_MINUTES ?= 30
SOAK_RATE ?= 3
soak: build
	@test -f $(DEMO_DIR)/workbench.bag || $(MAKE) demo
	@set +u; source $(BUILD)/devel/setup.bash; set -u; ROS_PACKAGE_PATH=$(CURDIR):$$ROS_PACKAGE_PATH \
	  /usr/bin/python3 scripts/soak.py --bag $(DEMO_DIR)/workbench.bag --output $(BUILD)/soak \
	  --minutes $(SOAK_MINUTES) --rate $(SOAK_RATE)

# Latency image stamp -> tracked objects while replaying the default scenario at real time.
latency: build
	@scripts/latency.sh $(DEMO_DIR)/workbench.bag $(BUILD)/latency.json

# The keypoint detector: render labelled train and val sets, train for MODEL_MINUTES (wall clock),
# export models/sgt_keypoints.onnx + .yaml, evaluate on the held-out val set (build/model/eval).
# The shipped model: 80 minutes on this 2-core machine (shared with builds); longer trains better.
MODEL_DIR ?= $(BUILD)/model
MODEL_MINUTES ?= 80
MODEL_TRAIN_IMAGES ?= 6000
MODEL_VAL_IMAGES ?= 400
MODEL_TRAIN_SEED ?= 1
MODEL_MAX_DISTANCE ?= 2.5
MODEL_LR ?= 3e-3
# The share of bench scenes like the robot's in the train and val renders (render_dataset --bench-fraction)
MODEL_BENCH_FRACTION ?= 0
MODEL_VAL_BENCH_FRACTION ?= 0
# Keypoint labels: object (up to the object's symmetries) or cuboid (up to a half turn of its box too)
MODEL_LABELS ?= object
# Score thresholds by the best F-beta on the val set (evaluate_detector --threshold-beta)
MODEL_THRESHOLD_BETA ?= 1
# The classes to detect: an object catalog (its classes in its order) and, if its meshes are elsewhere,
# their directory; e.g. MODEL_CATALOG=config/real/visp_rbt.yaml MODEL_MESH_DIR=../shared/data/real/visp_rbt/models
MODEL_CATALOG ?= package://scene_graph_tracker/config/objects.yaml
MODEL_MESH_DIR ?=
MODEL_CLASSES = --catalog $(MODEL_CATALOG) $(if $(MODEL_MESH_DIR),--mesh-dir $(MODEL_MESH_DIR))
# Appearance randomisation of the train renders (render_dataset --textures, --camera-effects): the
# probability that a surface is patterned, and that an image gets a camera's exposure, blur, noise, JPEG
MODEL_TEXTURES ?= 0
MODEL_CAMERA_EFFECTS ?= 0
# A directory of photographs for textures and backgrounds of the train renders (render_dataset --photos);
# make photos fills PHOTOS_DIR with a set; empty: none
MODEL_PHOTOS ?=
# Frames of generated scenarios like the suite's (render_dataset --scenarios): MODEL_SCENARIOS scenarios
# from MODEL_SCENARIO_SEED for the train set (its share MODEL_SCENARIO_FRACTION), a fifth as many from
# the next seed for the val set (its share MODEL_VAL_SCENARIO_FRACTION); 0: none. Keep the seed off
# the suite's (SUITE_SEED).
MODEL_SCENARIOS ?= 0
MODEL_SCENARIO_SEED ?= 101
MODEL_SCENARIO_FRACTION ?= 1
MODEL_VAL_SCENARIO_FRACTION ?= 0
MODEL_TRAIN_SCENARIOS = $(if $(filter-out 0,$(MODEL_SCENARIOS)),--scenarios $(MODEL_DIR)/scenarios/train \
  --scenario-fraction $(MODEL_SCENARIO_FRACTION))
MODEL_VAL_SCENARIOS = $(if $(filter-out 0,$(MODEL_SCENARIOS)),--scenarios $(MODEL_DIR)/scenarios/val \
  --scenario-fraction $(MODEL_VAL_SCENARIO_FRACTION))
# Where the trained model goes (its .yaml beside it); another path keeps the shipped one
MODEL_OUTPUT ?= models/sgt_keypoints.onnx
# MODEL_INIT=models/sgt_keypoints.onnx continues training from that model (warm start)
MODEL_INIT ?=
model: build
	@rm -rf $(MODEL_DIR)/train $(MODEL_DIR)/val $(MODEL_DIR)/scenarios && mkdir -p $(MODEL_DIR)
	$(if $(filter-out 0,$(MODEL_SCENARIOS)),$(TOOLS)/generate_scenarios --count $(MODEL_SCENARIOS) --seed $(MODEL_SCENARIO_SEED) \
	  --output $(MODEL_DIR)/scenarios/train $(MODEL_CLASSES) && $(TOOLS)/generate_scenarios \
	  --count $$(( ($(MODEL_SCENARIOS) + 4) / 5 )) --seed $$(( $(MODEL_SCENARIO_SEED) + 1 )) \
	  --output $(MODEL_DIR)/scenarios/val $(MODEL_CLASSES))
	$(TOOLS)/render_dataset --output $(MODEL_DIR)/train --count $(MODEL_TRAIN_IMAGES) --seed $(MODEL_TRAIN_SEED) \
	  --max-distance $(MODEL_MAX_DISTANCE) --bench-fraction $(MODEL_BENCH_FRACTION) --labels $(MODEL_LABELS) $(MODEL_CLASSES) \
	  --textures $(MODEL_TEXTURES) --camera-effects $(MODEL_CAMERA_EFFECTS) $(if $(MODEL_PHOTOS),--photos $(MODEL_PHOTOS)) \
	  $(MODEL_TRAIN_SCENARIOS)
	$(TOOLS)/render_dataset --output $(MODEL_DIR)/val --count $(MODEL_VAL_IMAGES) --seed 2 --max-distance $(MODEL_MAX_DISTANCE) \
	  --bench-fraction $(MODEL_VAL_BENCH_FRACTION) --labels $(MODEL_LABELS) $(MODEL_CLASSES) $(MODEL_VAL_SCENARIOS)
	set -o pipefail; /usr/bin/python3 scripts/train_detector.py --train $(MODEL_DIR)/train --val $(MODEL_DIR)/val \
	  --minutes $(MODEL_MINUTES) --lr $(MODEL_LR) $(if $(MODEL_INIT),--init $(MODEL_INIT)) --output $(MODEL_OUTPUT) \
	  --checkpoint-dir $(MODEL_DIR)/checkpoints 2>&1 | tee $(MODEL_DIR)/train.log
	$(TOOLS)/evaluate_detector --dataset $(MODEL_DIR)/val --model $(basename $(MODEL_OUTPUT)).yaml --output $(MODEL_DIR)/eval \
	  --write-thresholds --threshold-beta $(MODEL_THRESHOLD_BETA) $(MODEL_CLASSES)

# Photographs for MODEL_PHOTOS: the sample images of Debian's opencv-doc (OpenCV's samples/data, about
# 90 photos and test pictures), unpacked into PHOTOS_DIR without installing the package.
PHOTOS_DIR ?= $(BUILD)/photos
photos:
	@rm -rf $(PHOTOS_DIR) $(PHOTOS_DIR).deb && mkdir -p $(PHOTOS_DIR) $(PHOTOS_DIR).deb
	cd $(PHOTOS_DIR).deb && apt-get download opencv-doc && dpkg-deb -x opencv-doc_*.deb unpacked
	cp $(PHOTOS_DIR).deb/unpacked/usr/share/doc/opencv-doc/examples/data/*.jpg \
	  $(PHOTOS_DIR).deb/unpacked/usr/share/doc/opencv-doc/examples/data/*.png $(PHOTOS_DIR)/
	@rm -rf $(PHOTOS_DIR).deb && echo "photos: $$(ls $(PHOTOS_DIR) | wc -l) images in $(PHOTOS_DIR)"

# config/tracker.yaml, config/detector.yaml, cfg/Tracker.cfg and the README's parameter tables from
# the parameter schema (src/core/pipeline/parameter_schema.cpp); test_parameter_schema checks them.
params: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j$(JOBS) --target scene_graph_tracker_print_parameters
	$(TOOLS)/print_parameters --write $(CURDIR)

# libFuzzer targets (test/fuzz/, cmake/fuzz.cmake) in a clang build of their own ($(BUILD)/fuzz,
# ASan + UBSan), each run FUZZ_SECONDS on its seeds; findings in $(BUILD)/fuzz/artifacts/<target>/,
# the summary in $(BUILD)/fuzz/report.json. Fails when a target found anything.
FUZZ_SECONDS ?= 60
fuzz: deps
	@/usr/bin/python3 scripts/fuzz.py --build $(BUILD)/fuzz --seconds $(FUZZ_SECONDS) --jobs $(JOBS)

clean:
	rm -rf $(BUILD)
