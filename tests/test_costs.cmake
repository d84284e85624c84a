# COST of the long GoogleTest cases: their seconds in the ASan + UBSan CI build (ctest -j2, last
# measured 2026-12-03, build-ci/Testing/Temporary/CTestCostData.txt of a clean-clone run).
# ctest -j starts the costliest tests first, by its timing history; a fresh checkout has none, so
# without these a 56 s case could start last and run alone at the end. Included after the
# gtest_discover_tests lists of each test directory (tests/CMakeLists.txt); a name not defined in
# a directory is ignored. Tests registered with add_test carry their COST where they are added.
foreach(_socc_cost
    "PlaceRecognition.ClosesASimulatedLoopWithoutWrongClosures=56"
    "Relocalizer.AcceptsAfterConfirmationAndNotElsewhere=50"
    "ClosedLoop.AKidnappedRobotGetsLostAndStopsIntegrating=45"
    "PlaceRecognition.TwoRobotsInTwoWorldsNeverMeet=43"
    "AzimuthTimes.DeskewASimulatedStreetAsWellAsTheWrittenTimes=39"
    "OwnFrame.MergedIntoTheSharedFrameWhereItWasMappedNeverElsewhere=35"
    "Relocalize.AnUnmappedPlaceIsNotLocalized=35"
    "ClosedLoop.AFeaturelessCorridorWithSensorErrorsCoastsFlaggedAndKeepsTracking=34"
    "MapCorrection.AClosureRebuildsTheGridFromTheKeyframeScansAtTheOptimizedPoses=22"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/street/straight/hdl64/0=22"
    "OdometryEdge.ASnapAtTheRevisitIsSpreadOverTheLoopInsteadOfKept=21"
    "GlobalLocalizer.KittiReverseRevisitIsAmongTheCandidates=20"
    "ClosedLoop.ASparseSensorFollowsARollChange=20"
    "Relocalize.KittiReverseRevisitWithoutAGuess=19"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/street/straight/hdl64/20=19"
    # Not yet measured in CI: 14.6 s wall alone in build-ci flags at load 2 (AClosureRebuilds
    # there: 18.2 s for its 22), scaled.
    "MapCorrection.AWorkerFarBehindKeepsEveryKeyframeScanButBoundsTheQueuedClouds=18"
    "MapCorrection.TheServiceSwapsTheGridInAndTellsTheRobotItsCorrectionOnce=16"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/street/straight/vlp32/22=16"
    "MapCorrection.AServiceRestartedFromItsStoreRebuildsWithTheKeyframesFromBeforeTheRestart=15"
    # Measured in the clean-clone CI of 2026-12-06: 29.9 s.
    "MapCorrection.LaterRebuildsOfTheMovedRegionGiveTheMapOfAWholeRebuild=30"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/street/straight/vlp32/14=13"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/street/circle/vlp16/9=11"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/indoor/auto/vlp32/0=10"
    "Space/ClosedLoopDistortion.ConvergesAndStaysCloseToGroundTruth/office/auto/vlp32/0=10")
  string(REGEX MATCH "^(.*)=([0-9]+)$" _socc_match "${_socc_cost}")
  set_tests_properties("${CMAKE_MATCH_1}" PROPERTIES COST ${CMAKE_MATCH_2})
endforeach()
