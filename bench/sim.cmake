# Simulator speed (issue 3).
add_executable(cogmap_sim_bench ${CMAKE_CURRENT_LIST_DIR}/sim_bench.cc)
target_link_libraries(cogmap_sim_bench PRIVATE cogmap_sim cogmap_io benchmark::benchmark)
target_compile_definitions(cogmap_sim_bench PRIVATE COGMAP_SHARED_DIR="${COGMAP_SHARED_DIR}")
