# Loaded by find_package(assistive_eval): how a stage builds a benchmark CLI against this package.
#
#   assistive_eval_add_benchmark(<target> <sources>... [LIBRARIES <libraries>...])
#
# builds <target> with assistive_eval's headers and libraries (plus LIBRARIES, e.g. the stage's
# core) and installs it into the package's bin folder (rosrun <package> <target>).
function(assistive_eval_add_benchmark target)
  cmake_parse_arguments(ARG "" "" "LIBRARIES" ${ARGN})
  add_executable(${target} ${ARG_UNPARSED_ARGUMENTS})
  target_include_directories(${target} PRIVATE ${assistive_eval_INCLUDE_DIRS})
  target_link_libraries(${target} ${ARG_LIBRARIES} ${assistive_eval_LIBRARIES})
  install(TARGETS ${target} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endfunction()
