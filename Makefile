# scene_graph_tracker — developer entry points. See README.md.
SHELL := /bin/bash
export PATH := /usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
BUILD ?= build
JOBS ?= 2
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DCATKIN_DEVEL_PREFIX=$(CURDIR)/$(BUILD)/devel

.PHONY: deps build test bench clean

deps:
	@scripts/install-deps.sh

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j$(JOBS)

test: build
	@rm -rf $(BUILD)/test_results
	cmake --build $(BUILD) -j$(JOBS) --target tests
	-@cmake --build $(BUILD) --target run_tests -- -k > $(BUILD)/run_tests.log 2>&1; true
	@/usr/bin/python3 scripts/test_summary.py $(BUILD)/test_results $(BUILD)/run_tests.log

bench: build
	cmake --build $(BUILD) -j$(JOBS) --target benchmarks
	@scripts/run-benchmarks.sh $(BUILD)

clean:
	rm -rf $(BUILD)
