# `cogmap grid` (issue 2, grid part).
target_sources(cogmap PRIVATE ${CMAKE_CURRENT_LIST_DIR}/cmd_grid.cc)
target_link_libraries(cogmap PRIVATE cogmap_grid cogmap_io)
