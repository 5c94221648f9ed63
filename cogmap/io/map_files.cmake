# The master map's files (issue 5; owned by the ASR part): SVG, PNG, map_server
# PGM + YAML, GeoJSON, ARIA 2D-Map.
target_sources(cogmap_io PRIVATE ${CMAKE_CURRENT_LIST_DIR}/map_files.cc)
target_link_libraries(cogmap_io PUBLIC cogmap_asr)
cogmap_add_test(cogmap_map_files_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/map_files_test.cc
  LIBS cogmap_io nlohmann_json::nlohmann_json)
