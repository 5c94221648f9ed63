# Scale benchmark of the cognitive mapper (issue 5, ASR part): time per reading
# and peak memory at 10 % and 100 % of a long run (see map_bench.cc).
add_executable(cogmap_map_bench ${CMAKE_CURRENT_SOURCE_DIR}/map_bench.cc)
target_include_directories(cogmap_map_bench PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(cogmap_map_bench PRIVATE cogmap_asr cogmap_localize cogmap_io nlohmann_json::nlohmann_json)
