# World files (2D-Map, bitmap worlds): owned by the simulator part.
target_sources(cogmap_io PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/world_io.cc)

cogmap_add_test(cogmap_world_io_test
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/world_io_test.cc
  LIBS cogmap_io cogmap_sim)  # cogmap_sim: a ROS-map world simulated (issue 12)
