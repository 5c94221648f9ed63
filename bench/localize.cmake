# Heading correction: EM time per ASR (SPEC 5).
add_executable(cogmap_localize_bench ${CMAKE_CURRENT_SOURCE_DIR}/localize_bench.cc)
target_include_directories(cogmap_localize_bench PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(cogmap_localize_bench PRIVATE cogmap_localize benchmark::benchmark)
