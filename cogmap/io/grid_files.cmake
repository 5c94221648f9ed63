# Grid pictures and the ROS map_server pair (owned by the grid part).
target_sources(cogmap_io PRIVATE ${CMAKE_CURRENT_LIST_DIR}/grid_io.cc)
cogmap_add_test(cogmap_grid_io_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/grid_io_test.cc
  LIBS cogmap_io cogmap_grid)
