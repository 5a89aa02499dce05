# The project's commands. `make demo` and `make test` are the two a new user runs;
# both install what is missing first. See README.md.
SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
WS := $(ROOT)/catkin_ws
# catkin needs the system Python (a pyenv python3 without catkin_pkg may shadow it).
export PATH := /usr/bin:$(PATH)
CATKIN_CMD := cd $(WS) && catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3
CATKIN := $(CATKIN_CMD) -j2
ENV := source $(WS)/devel/setup.bash

.PHONY: all deps build test demo bench lint format clean

all: build

deps:
	@bash $(ROOT)/scripts/install_deps.sh

build: deps
	@$(CATKIN)

# Every gtest and rostest, then one summary line `N passed, N failed`. Test
# binaries build in parallel; the tests run one at a time, because some share
# one resource (the loopback GigE camera port, a pseudo-terminal, a master).
test: build
	@rm -rf $(WS)/build/test_results
	@$(CATKIN) tests > $(WS)/run_tests.log 2>&1 || \
	  { grep -E 'error|Error' $(WS)/run_tests.log | head -40; echo "make test: see $(WS)/run_tests.log"; }
	@$(CATKIN_CMD) -j1 run_tests >> $(WS)/run_tests.log 2>&1 || \
	  { grep -E 'error|Error' $(WS)/run_tests.log | head -40; echo "make test: see $(WS)/run_tests.log"; }
	@grep -E '^\[  (FAILED|PASSED) |^\[ROSTEST\]|FAILURE' $(WS)/run_tests.log || true
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
