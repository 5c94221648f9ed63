add_executable(cogmap_grid_bench ${CMAKE_CURRENT_SOURCE_DIR}/grid_bench.cc)
target_include_directories(cogmap_grid_bench PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(cogmap_grid_bench PRIVATE cogmap_grid benchmark::benchmark)
