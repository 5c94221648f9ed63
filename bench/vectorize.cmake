# Vectorization (issue 4): time per stage, and OpenCV side by side on known
# synthetic room layouts.
add_executable(cogmap_vectorize_bench ${CMAKE_CURRENT_SOURCE_DIR}/vectorize_bench.cc)
target_include_directories(cogmap_vectorize_bench PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(cogmap_vectorize_bench PRIVATE cogmap_vectorize benchmark::benchmark)

find_package(OpenCV QUIET COMPONENTS core imgproc)
if(OpenCV_FOUND)
  add_executable(cogmap_opencv_compare ${CMAKE_CURRENT_SOURCE_DIR}/opencv_compare.cc)
  target_include_directories(cogmap_opencv_compare PRIVATE ${PROJECT_SOURCE_DIR})
  target_include_directories(cogmap_opencv_compare SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_link_libraries(cogmap_opencv_compare PRIVATE cogmap_vectorize cogmap_eval opencv_core opencv_imgproc)
endif()
