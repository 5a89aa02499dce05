# The project's commands. `make demo` and `make test` are the two a new user runs;
# both install what is missing first. See README.md.
SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
WS := $(ROOT)/catkin_ws
# catkin needs the system Python (a pyenv python3 without catkin_pkg may shadow it).
export PATH := /usr/bin:$(PATH)
# cmake/workspace.cmake: unity builds and ctest's test locks and costs for every package (included after each project()).
CATKIN_CMD := cd $(WS) && catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_PROJECT_INCLUDE=$(ROOT)/cmake/workspace.cmake
CATKIN := $(CATKIN_CMD) -j2
ENV := source $(WS)/devel/setup.bash

.PHONY: all deps build test demo bench lint format clean

all: build

deps:
	@bash $(ROOT)/scripts/install_deps.sh

build: deps
	@$(CATKIN)

# Every gtest and rostest, then one summary line `N passed, N failed`. The build and the test
# binaries are one make graph (the target ws_all_and_tests, cmake/workspace.cmake), so both cores
# stay busy to the end; if the build itself fails, make test stops as `make build` would, while a test
# binary that does not compile is reported and the tests run. ctest runs two tests at a time, except
# that tests sharing one resource (the loopback GigE camera port, a pipeline replayed in real time)
# hold a RESOURCE_LOCK and run one after the other, and that soak_short takes both of the two cpu
# slots of cmake/ctest_cpu.json, so only short light tests run beside it (cmake/workspace.cmake).
# Each test has its own master, pty and files. Three lanes (ctest -j3) saved about 40 s but
# look_away_recovery's overlay check then failed in 2 of 3 full runs (.ci/README.md), so two it is.
test: deps
	@rm -rf $(WS)/build/test_results
	@set -o pipefail; $(CATKIN) ws_all_and_tests 2>&1 | tee $(WS)/run_tests.log || \
	  { $(CATKIN) > /dev/null 2>&1 || { echo "make test: the build failed (above)"; exit 1; }; \
	    grep -E 'error|Error' $(WS)/run_tests.log | head -40; echo "make test: see $(WS)/run_tests.log"; }
	@cd $(WS)/build && ctest -j2 --resource-spec-file $(ROOT)/cmake/ctest_cpu.json -V >> $(WS)/run_tests.log 2>&1 || \
	  { grep -E 'error|Error' $(WS)/run_tests.log | head -40; echo "make test: see $(WS)/run_tests.log"; }
	@grep -E '^([0-9]+: )?(\[  (FAILED|PASSED) |\[ROSTEST\]|.*FAILURE)' $(WS)/run_tests.log || true
	@bash $(ROOT)/scripts/test_summary.sh $(WS)/build/test_results

demo: build
	@$(ENV) && bash $(ROOT)/scripts/demo.sh $(ROOT)/out

bench: build
	@$(ENV) && bash $(ROOT)/scripts/bench.sh

lint: deps
	@cd $(ROOT) && catkin_lint -W2 --strict src
	@cd $(ROOT) && bash scripts/clang_format.sh --check

format:
	@cd $(ROOT) && bash scripts/clang_format.sh --fix

clean:
	rm -rf $(WS)/build $(WS)/devel $(WS)/run_tests.log $(ROOT)/src/CMakeLists.txt $(ROOT)/out

# ---- rig_sim (issue 3): simulated bags ----------------------------------------------------------
# `make bags` regenerates the full-size scenario set into rosbags/full/ (ignored by git) and runs the
# validator on each; `make sample_bags` regenerates the small committed samples in rosbags/.
.PHONY: bags sample_bags
RIG_SIM_SCENARIOS := handheld still shake look_away clutter stacked indoor
bags: build
	@mkdir -p $(ROOT)/rosbags/full
	@$(ENV) && for s in $(RIG_SIM_SCENARIOS); do \
	  rosrun rig_sim make_bag --scenario $$s --seed 1 --output $(ROOT)/rosbags/full/$$s.bag || exit 1; \
	  rosrun rig_sim validate_bag $(ROOT)/rosbags/full/$$s.bag > $(ROOT)/rosbags/full/$$s.validation.txt \
	    || { cat $(ROOT)/rosbags/full/$$s.validation.txt; exit 1; }; \
	  tail -1 $(ROOT)/rosbags/full/$$s.validation.txt; \
	done

sample_bags: build
	@$(ENV) && bash $(ROOT)/src/rig_sim/scripts/make_sample_bags.sh $(ROOT)/rosbags

# ---- cone_tracker (issue 4): chapter 7.1 experiments, figures 9.1-9.9, the cone
# layout and the 7.1.3 Monte Carlo tables, written to out/experiments/.
.PHONY: experiments
experiments: build
	@mkdir -p $(ROOT)/out/experiments
	@$(ENV) && $(WS)/devel/lib/cone_tracker/cone_tracker_experiments --out $(ROOT)/out/experiments \
	  | tee $(ROOT)/out/experiments/report.txt
	@/usr/bin/python3 $(ROOT)/src/cone_tracker/scripts/plot_experiments.py $(ROOT)/out/experiments

# ar_overlay: rviz with src/ar_overlay/rviz/overlay.rviz under Xvfb, on stand-in data
# (rviz_demo.launch), screenshot to out/rviz_overlay.png.
.PHONY: rviz-screenshot
rviz-screenshot: build
	@mkdir -p $(ROOT)/out
	@$(ENV) && bash $(ROOT)/src/ar_overlay/scripts/rviz_screenshot.sh $(ROOT)/out/rviz_overlay.png 25

# ar_overlay: the overlay test platform of thesis 7.2 (figures 7.8 and 7.9): rig_sim handheld bags of
# layouts/platform.yaml replayed through the whole graph with pose_ekf's gyros on and off, the red
# dots' misalignment measured in every overlay frame; tables in out/experiments/overlay_platform.md.
# PLATFORM_TRIALS, PLATFORM_DURATION_S and PLATFORM_RATE shorten or slow the run.
.PHONY: overlay-platform
PLATFORM_TRIALS ?= 3
PLATFORM_DURATION_S ?= 30
PLATFORM_RATE ?= 0.5
overlay-platform: build
	@mkdir -p $(ROOT)/out/experiments
	@$(ENV) && bash $(ROOT)/src/ar_overlay/scripts/overlay_platform.sh $(ROOT)/out/experiments \
	  $(PLATFORM_TRIALS) $(PLATFORM_DURATION_S) $(PLATFORM_RATE)

# cone_tracker (issue 15): detect_cones on the labelled real photos of ../shared/data/images/tracon_train
# (skipped when absent), scored by evaluate_detections against their YOLO labels: precision, recall,
# AP50, the missed and false boxes, the PR curve and a contact sheet of the worst images in out/eval_photos/.
.PHONY: eval-photos
EVAL_PHOTOS := $(abspath $(ROOT)/../shared/data/images/tracon_train/images)
eval-photos: build
	@if [[ ! -d "$(EVAL_PHOTOS)" ]]; then \
	  echo "eval-photos: skipped, $(EVAL_PHOTOS) is not there (the labelled photos, see cone_tracker's README)"; \
	  exit 0; fi; \
	mkdir -p $(ROOT)/out/eval_photos && $(ENV) && shopt -s nullglob && \
	images=("$(EVAL_PHOTOS)"/*) && \
	rc=0; rosrun cone_tracker detect_cones --config photos --output $(ROOT)/out/eval_photos/detections.jsonl \
	  "$${images[@]}" || rc=$$?; \
	if [[ $$rc -gt 1 ]]; then exit $$rc; fi; \
	if [[ $$rc == 1 ]]; then echo "eval-photos: detect_cones could not read some images (above); scoring the rest"; fi; \
	rosrun cone_tracker evaluate_detections $(ROOT)/out/eval_photos/detections.jsonl --output-dir $(ROOT)/out/eval_photos

# Tracking by the cones in the true view (issue 16's table): 512x384 rig_sim bags of handheld and
# look_away, asymmetric layout, held-out seeds (default 4 5; SEEDS="3 4 5 6"), into out/eval_tracking/.
.PHONY: eval-tracking
SEEDS ?= 4 5
eval-tracking: build
	@$(ENV) && bash $(ROOT)/scripts/eval_tracking.sh $(ROOT)/out/eval_tracking $(SEEDS)

# Tracking on rig_sim's `site` (14 cones over 19 m x 19 m, its own layout, often only one or two in
# view), seeds 1-5 (SITE_SEEDS), replayed at half rate (the 2-core machine drops frames otherwise),
# into out/eval_site/ (rig_sim's README, "Site tracking").
.PHONY: eval-site
SITE_SEEDS ?= 1 2 3 4 5
eval-site: build
	@$(ENV) && EVAL_SCENARIOS=site EVAL_ARGS="rate:=0.5 $(EVAL_ARGS)" \
	  bash $(ROOT)/scripts/eval_tracking.sh $(ROOT)/out/eval_site $(SITE_SEEDS)
