# Log readers and writers (issue 2, logs part).
target_sources(cogmap_io PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/log_lines.cc
  ${CMAKE_CURRENT_LIST_DIR}/log_reader.cc
  ${CMAKE_CURRENT_LIST_DIR}/native_log.cc
  ${CMAKE_CURRENT_LIST_DIR}/carmen_log.cc
  ${CMAKE_CURRENT_LIST_DIR}/pioneer_log.cc
  ${CMAKE_CURRENT_LIST_DIR}/ev3_log.cc)
target_link_libraries(cogmap_io PUBLIC nlohmann_json::nlohmann_json PRIVATE ZLIB::ZLIB)

cogmap_add_test(cogmap_log_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/native_log_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/carmen_log_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/pioneer_log_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/ev3_log_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/log_reader_test.cc
  LIBS cogmap_io ZLIB::ZLIB)

# A CARMEN SONAR log written from a simulated run (issue 12).
cogmap_add_test(cogmap_carmen_sonar_sim_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/carmen_sonar_sim_test.cc
  LIBS cogmap_io cogmap_sim cogmap_grid ZLIB::ZLIB)
