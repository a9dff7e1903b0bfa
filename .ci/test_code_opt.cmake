# Included after every project() of the workspace by .ci/build (CMAKE_PROJECT_INCLUDE), issue 31:
# the test executables' own code (gtest bodies, fixtures, rostest clients: targets named test_*)
# is compiled at ASSISTIVE_TEST_CODE_OPT (default -O1) instead of Release's -O3. Most of their
# compile time is template instantiation and optimisation of code that runs once; the libraries,
# nodelets, CLIs and benchmarks they exercise stay Release -O3, so what is tested and measured is
# the shipped build. Measured on test_assistive_vo_core's largest unity file: 21 s CPU at -O3, 16 s
# at -O1. -Og compiles 8-17 % faster still but runs the test code slower: test_assistive_vo_core
# took 104 s of CPU instead of 51 (tried, not kept). A plain `catkin_make` without this file builds
# the tests at -O3, slower but the same.
set(ASSISTIVE_TEST_CODE_OPT "-O1" CACHE STRING "optimisation of test_* targets' own code (.ci/test_code_opt.cmake)")
if(NOT COMMAND assistive_test_code_opt)
  function(assistive_test_code_opt)
    get_property(targets DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" PROPERTY BUILDSYSTEM_TARGETS)
    foreach(t IN LISTS targets)
      get_target_property(type ${t} TYPE)
      if(t MATCHES "^test_" AND type STREQUAL "EXECUTABLE")
        # after CMAKE_CXX_FLAGS_RELEASE on the command line: the last -O wins
        target_compile_options(${t} PRIVATE ${ASSISTIVE_TEST_CODE_OPT})
      endif()
    endforeach()
  endfunction()
endif()
cmake_language(DEFER CALL assistive_test_code_opt)
# and the precompiled headers (issue 31), wired the same way
include("${CMAKE_CURRENT_LIST_DIR}/pch.cmake")
# and GCC's garbage collection tuned down (issue 31)
include("${CMAKE_CURRENT_LIST_DIR}/gcc_gc.cmake")
