# `cogmap log-info` and `cogmap convert` (issue 2, logs part).
target_sources(cogmap PRIVATE ${CMAKE_CURRENT_LIST_DIR}/cmd_logs.cc)
target_link_libraries(cogmap PRIVATE cogmap_io)
