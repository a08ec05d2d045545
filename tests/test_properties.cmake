# Read by ctest after doctest's discovered-test list (TEST_INCLUDE_FILES of tests/): the suite
# runs with `ctest -j2` (scripts/test.sh), so the tests that measure time or memory, or that
# saturate the machine on purpose, run alone (RUN_SERIAL) instead of beside another test;
# everything else runs two at a time. A pattern here names tests by the prefix of their
# TEST_CASE name (a regular expression on the whole name).
#
# Why each group runs alone:
# - overload, deadline, drain, shutdown: they fill the compute pool and the queue and time how
#   fast a refusal or a drain comes; a neighbour test's CPU use would move those times;
# - replicas, scale-out, store outage: real rollgap processes, PostgreSQL and nginx with leases
#   and deadlines of a second or two, and a kill -9 in the middle;
# - edge (RSS): resident-memory bounds of a spawned service, which a neighbour's allocations do
#   not touch but whose timing loops do;
# - front proxy, connection: slow-client and keep-alive timeouts measured on the wire.
set(rollgap_serial_patterns
    "^shutdown:" "^drain:" "^deadline:" "^overload" "^replicas:" "^scale-out" "^store outage"
    "^front proxy" "^connection:" "^edge:")

# rollgap_test_runners: from runners.cmake (tests/CMakeLists.txt); each runner's discovered
# names are in <runner>_TESTS.
foreach(rollgap_runner IN LISTS rollgap_test_runners)
  foreach(rollgap_test IN LISTS ${rollgap_runner}_TESTS)
    foreach(rollgap_pattern IN LISTS rollgap_serial_patterns)
      if(rollgap_test MATCHES "${rollgap_pattern}")
        set_tests_properties("${rollgap_test}" PROPERTIES RUN_SERIAL TRUE)
        break()
      endif()
    endforeach()
  endforeach()
endforeach()
