# Polylines as data, the SVG writer and the stages picture (issue 4; owned by
# the vectorize part).
target_sources(cogmap_io PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/polyline_io.cc
  ${CMAKE_CURRENT_LIST_DIR}/svg.cc
  ${CMAKE_CURRENT_LIST_DIR}/stages_picture.cc)
target_link_libraries(cogmap_io PUBLIC cogmap_vectorize PRIVATE nlohmann_json::nlohmann_json)

cogmap_add_test(cogmap_vector_files_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/polyline_io_test.cc
  LIBS cogmap_io cogmap_vectorize)
