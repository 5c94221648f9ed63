# `cogmap map` (issue 5, ASR part).
target_sources(cogmap PRIVATE ${CMAKE_CURRENT_LIST_DIR}/cmd_map.cc)
target_link_libraries(cogmap PRIVATE cogmap_asr cogmap_localize cogmap_graph cogmap_io nlohmann_json::nlohmann_json)
