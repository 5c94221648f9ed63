# Peer comparisons and the benchmark suite (docs/BENCHMARKS.md).
#
# cogmap_mrpt_grid_compare: MRPT's COccupancyGridMap2D against cogmap's MHIMM
# on the same log; built only when MRPT 2 (Debian's libmrpt-dev) is found.
find_package(MRPT 2 QUIET COMPONENTS maps obs poses serialization io)
if(MRPT_FOUND AND TARGET mrpt::maps AND TARGET mrpt::obs)
  add_executable(cogmap_mrpt_grid_compare mrpt_grid_compare.cc)
  target_include_directories(cogmap_mrpt_grid_compare PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(cogmap_mrpt_grid_compare PRIVATE
    cogmap_io cogmap_grid cogmap_sensors cogmap_core
    ${MRPT_LIBRARIES} CLI11::CLI11 nlohmann_json::nlohmann_json)
  message(STATUS "cogmap: MRPT ${MRPT_VERSION} found, building cogmap_mrpt_grid_compare")
else()
  message(STATUS "cogmap: MRPT not found (scripts/install-deps.sh --peers), "
                 "no cogmap_mrpt_grid_compare; the suite shows its figures as n/a")
endif()

# The smoke-sized suite (one world, one robot, one seed, one drift): every
# metric present and finite. Slow-ish (simulates, maps and evaluates a run), so
# labelled "slow"; CI runs it.
if(COGMAP_BUILD_TESTS)
  find_program(COGMAP_PYTHON3 NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
  if(NOT COGMAP_PYTHON3)
    find_program(COGMAP_PYTHON3 NAMES python3)
  endif()
  if(COGMAP_PYTHON3)
    add_test(NAME bench_smoke
             COMMAND ${COGMAP_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/smoke
                     --build-dir ${CMAKE_BINARY_DIR} --shared ${COGMAP_SHARED_DIR})
    set_tests_properties(bench_smoke PROPERTIES TIMEOUT 900 LABELS slow)
  endif()
endif()

# cogmap_peer_opencv_vectorize: OpenCV findContours + approxPolyDP against
# cogmap's vectorization on the same cleaned grid; built when OpenCV is found.
find_package(OpenCV QUIET COMPONENTS core imgproc)
if(OpenCV_FOUND)
  add_executable(cogmap_peer_opencv_vectorize peer_opencv_vectorize.cc)
  target_include_directories(cogmap_peer_opencv_vectorize PRIVATE ${PROJECT_SOURCE_DIR})
  target_include_directories(cogmap_peer_opencv_vectorize SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_link_libraries(cogmap_peer_opencv_vectorize PRIVATE
    cogmap_io cogmap_vectorize cogmap_eval cogmap_grid cogmap_sensors cogmap_core
    opencv_core opencv_imgproc CLI11::CLI11 nlohmann_json::nlohmann_json)
else()
  message(STATUS "cogmap: OpenCV not found (scripts/install-deps.sh --peers), "
                 "no cogmap_peer_opencv_vectorize")
endif()

# A helper of the suite: heading errors of a map folder through
# cogmap::localize::ComputeHeadingErrors, used only while `cogmap eval` does
# not report the heading_error_deg_* keys itself.
add_executable(cogmap_suite_heading_eval suite/heading_eval.cc)
target_include_directories(cogmap_suite_heading_eval PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(cogmap_suite_heading_eval PRIVATE cogmap_localize cogmap_asr cogmap_core
                      nlohmann_json::nlohmann_json)
