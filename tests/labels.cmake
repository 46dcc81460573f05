# CTest labels beyond each test's module (its tests/<module> folder, set in tests/CMakeLists.txt).
# Included by CTest after the discovered tests, so the names below must be exact: the test
# Tests.LabelListsNameExistingTests fails on a stale one.
#   slow: a whole die, contact or study run (or every example deck checked), 2-90 s in Release on
#         2 cores and 10-20x that under the sanitizers (scripts/test-sanitized skips them; shorter
#         tests of the same kind cover their code paths there). Select with `ctest -L slow`, skip
#         with `ctest -LE slow`.
#   mpi:  runs pbxmpm under mpirun (LeakSanitizer reports Open MPI's own allocations at exit).
set(PBXMPM_LABELLED_TESTS
  analysis EngineBlock.HomogeneousElasticBlockInTheDieGivesBackKGE slow
  engine DieBlock.MassScalingKeepsTheCurveAndCutsSteps slow
  engine DieBlock.ConstrainedModulusLateralRatioAndQuasiStatic slow
  engine Threads.OneAndTwoThreadsGiveIdenticalHistories slow
  engine ContactMask.ContactSumsOnThePaperSpecimenEqualAFullScatter slow
  contact InclinedPlane.FieldPlaneSlidesAtCoulombAccelerationOrSticks slow
  contact InclinedPlane.UsfAndMuslSlideAtCoulombAccelerationOrStick slow
  contact InclinedPlane.NearTheFrictionLimitOnlyTheSuddenLoadsVibrationMakesABlockCreep slow
  contact Hertz.ContactHalfWidthOfACylinderOnAStiffFlat slow
  contact Hertz.ContactRadiusOfASphereOnAStiffFlat slow
  contact BinderLayer.DensestQuickRunStaysQuasiStaticAndBalancesItsForces slow
  contact BinderLayer.SpringsHandedThroughTheParticlesKeepTheSpecimensEnergyBalance slow
  contact BinderLayer.BondedZoneDeeperThanTheClosureKeepsTheSpringAtFineCells slow
  contact BinderLayer.AutomaticBondedZoneCoversTheLayersClosure slow
  contact ExtrudedSlab.ThreeDimensionalSlabOfAPackedSpecimenGivesThePlaneStrainCurves slow
  app Examples.EveryShippedDeckIsAccepted slow
  app Faults.RunsKilledAtRandomPointsResumeBitForBit slow
  app Faults.StudiesKilledAtRandomPointsResumeBitForBit slow
  app OwnStudy.BinderTwiceAsStiffIsAnsweredByTheConditionsTable slow,mpi
  app OwnStudy.PorosityQuestionIsAnsweredWithPairedSeeds slow,mpi
  study PaperDecks.CalibratedRunReadsTableThreeAt293K slow
  study Study.MpiTwoRanksEqualsSequentialAndResumes slow,mpi
  study Study.ResumedStudyUnderMpiKeepsBothRanksBusy slow,mpi
  study Study.RunFailingOnOneRankLeavesTheOtherRanksRunsWhole mpi
  study Study.StudyFolderThatCannotBeMadeEndsEveryRank mpi
  distributed StripExchange.RanksGiveTheOneProcessNodalSumsToTheBit mpi
  distributed StripExchange.RanksStepTheOneProcessDynamicsToTheBit slow,mpi
  distributed RunOverRanks.MpirunGivesTheOneProcessHistoryByteForByte mpi
  distributed RunOverRanks.EveryShapeFunctionGivesTheOneProcessHistory mpi
  distributed RunOverRanks.ThreeDimensionalRunGivesTheOneProcessHistory mpi
  distributed RunOverRanks.CheckpointWrittenOnTwoRanksRestartsOnAnyNumber mpi
  distributed RunOverRanks.MoreRanksThanTheGridAllowsAreRefused mpi)
list(LENGTH PBXMPM_LABELLED_TESTS n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 3)
  math(EXPR j "${i} + 1")
  math(EXPR k "${i} + 2")
  list(GET PBXMPM_LABELLED_TESTS ${i} module)
  list(GET PBXMPM_LABELLED_TESTS ${j} test)
  list(GET PBXMPM_LABELLED_TESTS ${k} labels)
  string(REPLACE "," ";" labels "${labels}")
  set_tests_properties(${test} PROPERTIES LABELS "${module};${labels}")
endforeach()
