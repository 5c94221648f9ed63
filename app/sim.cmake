# `cogmap simulate`, `render-world`, `gen-building` (issue 3, simulator part).
target_sources(cogmap PRIVATE ${CMAKE_CURRENT_LIST_DIR}/cmd_sim.cc)
target_link_libraries(cogmap PRIVATE cogmap_sim cogmap_io)
