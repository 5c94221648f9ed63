# `cogmap vectorize` and `cogmap eval` (issue 4, vectorize part).
target_sources(cogmap PRIVATE ${CMAKE_CURRENT_LIST_DIR}/cmd_vectorize.cc)
target_link_libraries(cogmap PRIVATE cogmap_vectorize cogmap_eval cogmap_asr cogmap_localize cogmap_grid cogmap_io nlohmann_json::nlohmann_json)
