# Included after every project() of the workspace: the Makefile passes
# -DCMAKE_PROJECT_INCLUDE=<this file> to catkin_make, so the packages' CMakeLists.txt need no line for it.
# Two things live here, both for `make test` on CI's 2 cores (keep the whole run well under 15 minutes):
#   1. build settings that cut the compile time (below, "Build": unity batches, the one target
#      ws_all_and_tests that `make test` builds, the test executables' -O1),
#   2. how ctest may run the tests two at a time (below, "Tests").
# Measurements behind both: .ci/README.md.

# ---- Build ----------------------------------------------------------------------------------------
# Unity builds: each target's sources are compiled a batch at a time as one translation unit
# (build/<pkg>/CMakeFiles/<target>.dir/Unity/unity_<n>_cxx.cxx), so the heavy headers (Eigen, OpenCV,
# Ceres, roscpp, gtest) are parsed, and their templates instantiated, once per batch instead of once
# per file. The price: the sources of one target share a translation unit, so two of them must not
# define the same file-local name (anonymous namespace or static). If they do, the build stops with
# "redefinition of '<name>'" (or "conflicting declaration", or "call of overloaded '<name>' is
# ambiguous" when a file-local function meets a header's of the same name), the note "In file included
# from .../Unity/unity_<n>_cxx.cxx" naming the batch. Fix it by giving the names unique names, by sharing
# one definition from a header, or by listing the source below (it then compiles on its own).
# A developer who prefers one object per file (faster single-file rebuilds) configures with
# -DWS_UNITY_BUILD=OFF.
option(WS_UNITY_BUILD "Compile each target's sources in batches (unity build)" ON)
set(CMAKE_UNITY_BUILD ${WS_UNITY_BUILD})
set(CMAKE_UNITY_BUILD_BATCH_SIZE 8)

# Sources that compile on their own, outside the unity batches. One a line: "<package> <path in the
# package>". Each defines a file-local name that another source of its target defines too; they are
# listed here rather than renamed while their packages are being edited. Any source can opt out the
# same way (or, in its package, set_source_files_properties(<file> PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)).
set(_WS_UNITY_SKIP
  "pose_ekf src/core/process_model.cpp"             # RotateInverse(Jacobian), as in cone_update.cpp
  "pose_ekf test/test_node_config.cpp"              # Write(name, text), as in test_adapter_cones.cpp
  "cone_tracker src/node/tracker_observations.cpp"  # Set2(), as in tracker_adapter.cpp
  "cone_tracker test/test_null_space.cpp"           # kExact, as in test_classic.cpp
  "cone_tracker test/test_refinement.cpp"           # View(frame), as in test_segmenter.cpp (ambiguous)
  "cone_tracker test/test_associate.cpp"            # LookAt() giving a Pose; vision_frames.h's gives a TruePose
)

# Targets compiled one object per source (UNITY_BUILD OFF), measured slower as batches: "<target>  # why".
set(_WS_UNITY_OFF
  # 17 sources of Eigen fixed-size algebra and Ceres: as three batches 170 + 78 + 2 CPU s, one by one 193 s
  # (cold, -O3, the same load); and the 170-s batch was the build's critical path (the rest of cone_tracker,
  # pose_ekf, ar_bringup and ar_overlay wait for this library) with one core idle meanwhile. .ci/README.md.
  "cone_tracker_pose"
  # EkfCore's updates split into sources of their own (one Update<M> instantiation each): batched, they would be
  # one translation unit again, the build's longest job. .ci/README.md.
  "pose_ekf_core"
)

function(_ws_apply_unity_skips)
  foreach(target IN LISTS _WS_UNITY_OFF)
    if(TARGET ${target})
      set_target_properties(${target} PROPERTIES UNITY_BUILD OFF)
    endif()
  endforeach()
  foreach(rule IN LISTS _WS_UNITY_SKIP)
    string(REGEX MATCH "^([^ ]+) ([^ ]+)$" _ "${rule}")
    if(CMAKE_MATCH_1 STREQUAL PROJECT_NAME)
      if(NOT EXISTS "${PROJECT_SOURCE_DIR}/${CMAKE_MATCH_2}")
        message(FATAL_ERROR "cmake/workspace.cmake _WS_UNITY_SKIP: ${PROJECT_NAME} has no source ${CMAKE_MATCH_2}")
      endif()
      set_source_files_properties("${PROJECT_SOURCE_DIR}/${CMAKE_MATCH_2}" PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
    endif()
  endforeach()
endfunction()

if(NOT PROJECT_NAME STREQUAL "Project")
  cmake_language(DEFER CALL _ws_apply_unity_skips)
endif()

# One make graph for the build and the test binaries: `make test` builds the target ws_all_and_tests,
# which depends on every target of the default build (`all`) and on catkin's `tests`. Built as
# `catkin_make` then `catkin_make tests`, the two phases each ended with one core idle (the last
# link or compile of the phase alone), and the test binaries, which need only their own libraries,
# waited for the whole of `all`. The targets of `all` are the ones not EXCLUDE_FROM_ALL (custom targets
# without ALL are), collected over the workspace's directories once every package is configured.
function(_ws_collect_all_targets dir out)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(dir_excluded DIRECTORY "${dir}" PROPERTY EXCLUDE_FROM_ALL)
  set(found)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    get_target_property(excluded ${target} EXCLUDE_FROM_ALL)
    if(excluded MATCHES "NOTFOUND$")
      set(excluded ${dir_excluded})
    endif()
    if(NOT type STREQUAL "INTERFACE_LIBRARY" AND NOT excluded)
      list(APPEND found ${target})
    endif()
  endforeach()
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    _ws_collect_all_targets("${sub}" sub_found)
    list(APPEND found ${sub_found})
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

# Test executables (the ones catkin's `tests` target builds: gtests and rostest gtests) compile at
# WS_TEST_OPTIMIZATION (-O1) instead of Release's -O3: their translation units are the harness (gtest,
# ROS, Eigen in the checks), 428 of the cold build's 1160 compile CPU s, and -O1 cuts them by a
# quarter (13 of the heaviest: 208 -> 156 CPU s; .ci/README.md). The libraries, nodes, nodelets and
# benchmarks the tests run stay at -O3 (NDEBUG stays too). Only the optimisation level changes: IEEE
# semantics (NaN checks included) and the target architecture stay those of every other target, so the
# results do not depend on it. -DWS_TEST_OPTIMIZATION=-O3 builds them as before.
set(WS_TEST_OPTIMIZATION "-O1" CACHE STRING "Optimisation flag for the test executables (after Release's -O3)")

# The benchmarks (*_bench) are not in it: no test runs them, and they are 77 of a cold build's 1462
# compile and link CPU s (.ci/README.md, fifth pass). `make build`, `make demo` and `make bench` build
# them (they are in `all`), so they still compile at every stop.
function(_ws_add_all_and_tests)
  _ws_collect_all_targets("${CMAKE_SOURCE_DIR}" targets)
  list(FILTER targets EXCLUDE REGEX "_bench$")
  add_custom_target(ws_all_and_tests)
  add_dependencies(ws_all_and_tests ${targets})
  if(TARGET tests)
    add_dependencies(ws_all_and_tests tests)
    get_property(test_targets TARGET tests PROPERTY MANUALLY_ADDED_DEPENDENCIES)
    foreach(target IN LISTS test_targets)
      get_target_property(type ${target} TYPE)
      if(type STREQUAL "EXECUTABLE" AND WS_TEST_OPTIMIZATION)
        set_property(TARGET ${target} APPEND PROPERTY COMPILE_OPTIONS ${WS_TEST_OPTIMIZATION})
      endif()
    endforeach()
  endif()
endfunction()

if(PROJECT_NAME STREQUAL "Project" AND CMAKE_CURRENT_SOURCE_DIR STREQUAL CMAKE_SOURCE_DIR)
  cmake_language(DEFER CALL _ws_add_all_and_tests)
endif()

# ---- Tests ----------------------------------------------------------------------------------------
# `make test` runs the tests with `ctest -j2 --resource-spec-file cmake/ctest_cpu.json`: two at a time,
# on two "cpu" slots. A test that holds a shared resource names it in a RESOURCE_LOCK, and ctest never
# runs two tests holding the same lock at once:
#   gige_loopback  arv-fake-gv-camera on 127.0.0.1, GVCP port 3956 (one camera per address)
#   realtime       the whole graph replayed or simulated in real time, with rate, latency or accuracy
#                  assertions that a second pipeline on the same 2 cores would disturb; the other slot
#                  runs unit tests and small rostests meanwhile. (relaunch_replay and two_hosts replay
#                  in real time too, but only wait for messages to arrive: no lock.)
# CPU slots (RESOURCE_GROUPS "cpu:<n>", only with the resource file): every test takes one slot, except
#   both_cpus      soak_short, which runs the simulator at twice real time and must lose no message. It
#                  takes both slots, so no other test that takes a slot runs beside it (beside a CPU-bound
#                  unit test, on the loaded shared machine, its probe dropped 49 of 4480 frames);
#   light          short tests (a few seconds: small rostests of config loading and one nodelet, unit
#                  tests under a few seconds) take none, so they run one at a time beside soak_short,
#                  on the core it left idle when it ran alone (RUN_SERIAL, before; .ci/README.md).
#                  Not light: anything on a pty or a camera, anything long or CPU-bound.
# COST (about the seconds each takes) makes ctest start the long ones first, so the two slots end
# together; ctest has no timing history on a fresh CI machine. Tests match by regular expression on
# their ctest names (_ctest_<package>_<type>_<name>; rostests of the repository's test/ carry its path).
# One rule a line: "<regex> <cost s> [<word>,<word>...]", each word a lock, both_cpus, light or
# RUN_SERIAL (the test runs alone); the first rule that matches applies. .ci/ctest_schedule.py reads
# these rules to model ctest's schedule on a run's test times.
set(_WS_TEST_RULES
  "aravis_camera_gtest_aravis_camera_test_fake_camera 30 gige_loopback"
  "aravis_camera_rostest_test_camera_nodelet 11 gige_loopback,realtime"
  "ar_bringup_rostest_.*soak_short 90 realtime,both_cpus"
  "ar_bringup_rostest_replay_handheld 36 realtime"
  "ar_bringup_rostest_look_away_recovery 26 realtime"
  # 24 s of bag replayed in real time (was set in ar_bringup's CMakeLists.txt, out of .ci/ctest_schedule.py's sight)
  "ar_bringup_rostest_site_reacquire 40 realtime"
  "ar_bringup_rostest_.*rig_check_(sim|no_imu|no_camera) 22 realtime"
  "ar_bringup_rostest_diagnostics_loop 12 realtime"
  "ar_bringup_rostest_relaunch_replay 11"
  "ar_bringup_rostest_two_hosts 11"
  "rig_sim_rostest_test_sim_launch 19 realtime"
  # CPU-bound for ~30 s (bundle adjustments of random layouts): beside replay_handheld it starved the
  # recorder (92 of 1800 images recorded, 2 December), so it takes the realtime lock too.
  "cone_survey_gtest_cone_survey_test 30 realtime"
  "cone_tracker_gtest_cone_tracker_dnn_test 14"
  "ar_demo_rostest_test_demo_report 20"
  "cone_tracker_gtest_cone_tracker_vision_test 18"
  "cone_tracker_gtest_cone_tracker_node_test 15"
  "cone_tracker_rostest_test_nodelet_bad_input 13"
  "pose_ekf_gtest_pose_ekf_broad_test 10"
  # Light (seconds alone, fresh clone; CPU used over that time, measured one at a time with /usr/bin/time):
  # one nodelet or a config load under its own master (1.2-5.6 s, 0.5-0.9 of a core), a script's CLI,
  # unit tests of under 3 s. Not imu_driver's pty tests (a 100 Hz stream on a pty) nor camera tests.
  "ar_overlay_rostest_test_overlay_nodelet 0 light"           # 5.3 s, 0.48 core; _predicted 5.6 s, 0.58
  "pose_ekf_rostest_test_(diagnostics_stay|nodelet_tf|load_config) 0 light"  # 5.5, 4.9, 3.0 s
  "imu_driver_rostest_test_(launch_files|real_data|scripts_cli|load_config) 0 light"  # 5.4, 5.1, 4.1, 3.6 s
  "ar_bringup_rostest_test_(rig_check|evaluation|probe_config) 0 light"  # 3.4, 2.9, 1.2 s: scripts and a config
  "cone_tracker_rostest_test_evaluate_detections 0 light"     # 3.6 s
  "ar_overlay_gtest_ar_overlay_test_core 0 light"             # 3.0 s
  "pose_ekf_gtest_pose_ekf_(rig_sim_test|test|adapter_test) 0 light"  # 3.0, 2.3, 0.2 s
  "rig_sim_gtest_rig_sim_test_(bags|validate_bag_cli) 0 light"  # 2.7, 0.6 s
  "ar_overlay_rostest_test_(tracking_panel|ros_config) 0 light"  # 2.5, 1.5 s
  "cone_tracker_gtest_cone_tracker_(tools_test|photos_test|pose_test) 0 light"  # 2.0, 1.7, 0.2 s
  "rig_model_.*test 0 light"                                  # load_params 1.7, wall_diagnostics 1.9 s, gtests 0.1 s
  "rig_sim_rostest_test_sim_params 0 light"                   # 1.3 s
  "aravis_camera_(rostest_test_ros_config|gtest_aravis_camera_test_units) 0 light"  # 1.3, 0.04 s
  "cone_tracker_roslaunch-check_launch 0 light"               # 0.8 s
  "(ar_bringup_python_core_layers|ar_bringup_gtest|compressed_transport_gtest|pose_math_gtest|imu_driver_gtest_imu_driver_(ros_)?test$|ar_overlay_gtest_ar_overlay_test_panel_model) 0 light"  # each under 0.3 s
)

function(_ws_apply_test_rules)
  get_directory_property(tests TESTS)
  foreach(test IN LISTS tests)
    set(cpus 1)
    foreach(rule IN LISTS _WS_TEST_RULES)
      string(REGEX MATCH "^([^ ]+) ([0-9]+) ?(.*)$" _ "${rule}")
      set(regex "${CMAKE_MATCH_1}")
      set(cost "${CMAKE_MATCH_2}")
      string(REPLACE "," ";" words "${CMAKE_MATCH_3}")
      if(test MATCHES "^_ctest_${regex}")
        set_tests_properties(${test} PROPERTIES COST ${cost})
        set(locks)
        foreach(word IN LISTS words)
          if(word STREQUAL "RUN_SERIAL")
            set_tests_properties(${test} PROPERTIES RUN_SERIAL ON)
          elseif(word STREQUAL "both_cpus")
            set(cpus 2)
          elseif(word STREQUAL "light")
            set(cpus 0)
          else()
            list(APPEND locks ${word})
          endif()
        endforeach()
        if(locks)
          set_tests_properties(${test} PROPERTIES RESOURCE_LOCK "${locks}")
        endif()
        break()
      endif()
    endforeach()
    # CPU slots (cmake/ctest_cpu.json, used only when ctest is given the file).
    if(cpus GREATER 0)
      set_tests_properties(${test} PROPERTIES RESOURCE_GROUPS "cpu:${cpus}")
    endif()
  endforeach()
endfunction()

if(NOT PROJECT_NAME STREQUAL "Project")  # catkin's toplevel project holds no test
  cmake_language(DEFER CALL _ws_apply_test_rules)
endif()
