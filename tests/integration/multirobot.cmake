# Multi-robot, log-replay and server-restart tests (included from
# tests/integration/CMakeLists.txt): real map_server, odom_client, socc-cli, socc-to-lcmlog /
# socc-sim processes and lcm-logplayer over UDP multicast on loopback (random port 50000-59999).
# See multirobot_test.sh --help. COST: the seconds of each test in the ASan CI build (clean-clone
# run of 2026-12-03, ctest -j2 on the loaded 2-core machine): a fresh checkout has no ctest timing
# history, and ctest -j starts the costliest tests first by it (also tests/test_costs.cmake).
# Each of these tests keeps about 2 threads runnable on average (socc-sim, map_server and
# odom_client use TBB; sampled from /proc every 0.2 s: odom_lost 1.92, relocalize 1.65), so at
# ctest -j2 on 2 cores they are CPU-bound: splitting a test into parallel parts or a higher -j
# would not shorten the run; only less work does.
if(TARGET map_server AND TARGET odom_client AND TARGET socc-cli)
  set(_socc_mr_script ${CMAKE_CURRENT_LIST_DIR}/multirobot_test.sh)
  set(_socc_mr_bins --server $<TARGET_FILE:map_server> --client $<TARGET_FILE:odom_client>
                    --cli $<TARGET_FILE:socc-cli>)
  if(TARGET socc-to-lcmlog)
    # odom_client --live fed by lcm-logplayer == odom_client --kitti on frames 0-7 (skipped, exit
    # code 77, when the shared data folder is absent).
    add_test(NAME integration.multirobot_logplayer
             COMMAND bash ${_socc_mr_script} logplayer ${_socc_mr_bins}
                     --to-lcmlog $<TARGET_FILE:socc-to-lcmlog> --data ${SOCC_SHARED_DATA_DIR})
    set_tests_properties(integration.multirobot_logplayer PROPERTIES
      LABELS integration TIMEOUT 120 SKIP_RETURN_CODE 77 COST 11)
  endif()
  if(TARGET socc-sim)
    # 3 clients on three segments of a socc-sim sequence + 1 server; GET_STATS lists 3 robots,
    # pose histories, accuracy with 3 robots vs alone.
    add_test(NAME integration.multirobot_robots
             COMMAND bash ${_socc_mr_script} robots ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.multirobot_robots PROPERTIES LABELS integration TIMEOUT 120 COST 24)
    # One of the 3 clients is killed with -9 mid-run and resumes from the server-held pose.
    add_test(NAME integration.multirobot_client_restart
             COMMAND bash ${_socc_mr_script} client_restart ${_socc_mr_bins}
                     --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.multirobot_client_restart PROPERTIES
      LABELS integration TIMEOUT 120 COST 13)
    # odom_client survives a kill -9 + --restore of map_server mid-run: exit 0, every scan
    # integrated exactly once, same map and poses as an undisturbed run.
    add_test(NAME integration.odom_server_restart
             COMMAND bash ${_socc_mr_script} server_restart ${_socc_mr_bins}
                     --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.odom_server_restart PROPERTIES LABELS integration TIMEOUT 180 COST 27)
    # A kidnapped robot (scans of another world from frame 10) gets lost, searches in vain, exits
    # 3, is LOST on the server, and leaves the shared map as frames 0-9 alone made it; one put
    # down again on its route recovers by itself (issue 27).
    add_test(NAME integration.odom_lost
             COMMAND bash ${_socc_mr_script} lost ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.odom_lost PROPERTIES LABELS integration TIMEOUT 600 COST 290)
    # Healthy robots stay healthy (issue 27): a 2 Hz PCD folder without time stamps, an indoor
    # lap, a recording with dropped scans.
    add_test(NAME integration.odom_health
             COMMAND bash ${_socc_mr_script} health ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.odom_health PROPERTIES LABELS integration TIMEOUT 480 COST 116)
    # Relocalization: a robot joins A's map without a pose, one from an unmapped place is not
    # localized (exit 4), a kidnapped robot recovers (docs/relocalization.md).
    add_test(NAME integration.relocalize
             COMMAND bash ${_socc_mr_script} relocalize ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.relocalize PROPERTIES LABELS integration TIMEOUT 480 COST 167)
    # Issue 30 stage 4: a robot started where nothing is mapped maps in its own frame and is
    # merged into A's map when it reaches it; one that never does is not (docs/relocalization.md).
    # A live robot (lcm-logplayer) searches beside its scan loop.
    set(_socc_mr_lcmlog)
    if(TARGET socc-to-lcmlog)
      set(_socc_mr_lcmlog --to-lcmlog $<TARGET_FILE:socc-to-lcmlog>)
    endif()
    add_test(NAME integration.own_frame
             COMMAND bash ${_socc_mr_script} own_frame ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>
                     ${_socc_mr_lcmlog})
    set_tests_properties(integration.own_frame PROPERTIES LABELS integration TIMEOUT 600 COST 280)
    # Issue 30 stage 4: on an empty server an own-frame robot with --found-map founds the map;
    # a second one is refused and merged into it (docs/relocalization.md "Founding an empty map").
    add_test(NAME integration.found_map
             COMMAND bash ${_socc_mr_script} found_map ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.found_map PROPERTIES LABELS integration TIMEOUT 360 COST 60)
    # Issue 27: a robot tracks with short round trips (no timeout, no unhealthy frame) while
    # another robot's LOCALIZE searches run on the server's search thread.
    add_test(NAME integration.busy_search
             COMMAND bash ${_socc_mr_script} busy_search ${_socc_mr_bins} --sim $<TARGET_FILE:socc-sim>)
    set_tests_properties(integration.busy_search PROPERTIES LABELS integration TIMEOUT 360 COST 47)
  endif()
endif()
