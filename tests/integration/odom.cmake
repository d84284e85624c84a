# odom_client end-to-end tests (included from tests/integration/CMakeLists.txt): a real
# map_server and odom_client processes over UDP multicast on loopback (random port 40000-49999).
if(TARGET map_server AND TARGET odom_client)
  add_executable(test_odom_integration ${CMAKE_CURRENT_LIST_DIR}/odom_integration_test.cpp)
  target_link_libraries(test_odom_integration PRIVATE socc_odom socc_rpc GTest::gtest_main)
  target_compile_definitions(test_odom_integration PRIVATE
    SOCC_SHARED_DATA_DIR="${SOCC_SHARED_DATA_DIR}"
    SOCC_MAP_SERVER_BIN="$<TARGET_FILE:map_server>"
    SOCC_ODOM_CLIENT_BIN="$<TARGET_FILE:odom_client>"
    SOCC_SIM_BIN="$<TARGET_FILE:socc-sim>"
    SOCC_BAG_FIXTURES_DIR="${CMAKE_BINARY_DIR}/tests/sensors/bag_fixtures")
  add_dependencies(test_odom_integration map_server odom_client socc-sim)
  socc_target_warnings(test_odom_integration)
  add_test(NAME integration.odom COMMAND test_odom_integration
           --gtest_filter=-OdomOnSimulatedDrive.*)
  # Every KITTI case skips (GTEST_SKIP) without the shared data: ctest must say skipped.
  # The bag with an IMU topic: written by the independent writers (tests/sensors).
  set_tests_properties(integration.odom PROPERTIES LABELS integration TIMEOUT 240 COST 18
                       SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]"
                       FIXTURES_REQUIRED bag_fixtures)
  # Accuracy against socc-sim's exact GT: needs no shared data, never skips.
  add_test(NAME integration.odom_sim COMMAND test_odom_integration
           --gtest_filter=OdomOnSimulatedDrive.*)
  set_tests_properties(integration.odom_sim PROPERTIES LABELS integration TIMEOUT 600 COST 86)
  # The benchmark script's report and its interleaved --repeat runs.
  add_test(NAME integration.bench_odometry_script
           COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/bench_script_test.sh ${PROJECT_SOURCE_DIR}
                   ${CMAKE_BINARY_DIR})
  set_tests_properties(integration.bench_odometry_script PROPERTIES LABELS integration TIMEOUT 240 COST 12)
endif()
