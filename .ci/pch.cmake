# Precompiled headers for the workspace's targets (issue 31), included by .ci/test_code_opt.cmake
# (so after every project() of a `.ci/build`; a plain `catkin_make` builds without them, the same
# code). Most translation units of a target parse the same external headers (gtest, roscpp and its
# messages, Eigen, OpenCV, tf2, ...): a target with more than one translation unit parses them once,
# into a precompiled header (CMake target_precompile_headers), instead of once per unit.
#   - The headers are those the target's own sources and the workspace headers they include name
#     with #include <...>, limited to the families below (no workspace headers, so editing one of
#     ours does not rebuild a PCH, and no generated message headers of assistive_msgs).
#   - A PCH is compiled with the target's own flags (Release -O3 -fPIC for libraries, -O1 for the
#     test_* executables): what is compiled is unchanged, only parsed once.
#   - The test_* executables of one package that have the same include folders, definitions,
#     options and libraries share one PCH (REUSE_FROM the largest of them, the union of their
#     headers). Only those: GCC refuses a PCH made with a macro the user does not define (measured:
#     "not used because `PKG_DIR' not defined", CMake passes -Winvalid-pch), and then parses
#     cmake_pch.hxx as text, which fails where the user lacks an include folder of the donor.
#   - Only for ASSISTIVE_PCH_MIN_UNITS translation units or more (a target's, or the package's
#     test executables' together): compiling the PCH costs more than parsing its headers once (it
#     holds the union of the units' headers), and measured on assistive_planner_core (2 units) the
#     PCH alone took 8.7 s of CPU (machine loaded) where the whole target had taken 9.8 s without
#     one (less loaded). GCC 12 spends most of it writing the PCH (-ftime-report: "PCH pointer
#     sort", "main state save"): test_slam_places's headers (ROS, rosbag, tf2, gtest) take 2.9 s
#     to parse in a unit, 16-18 s into a 395 MB PCH; shared by test_slam_fastslam it saved the two
#     4.5 and 5 s (a loss of 8.6 s), so a PCH does not pay for the nodelets, CLIs and rostest
#     clients of one or two units.
# ASSISTIVE_PCH=OFF (cache) turns it off.
option(ASSISTIVE_PCH "precompiled headers for targets with several translation units (.ci/pch.cmake)" ON)
set(ASSISTIVE_PCH_MIN_UNITS 4 CACHE STRING "fewest translation units that get a PCH (.ci/pch.cmake)")
set(ASSISTIVE_PCH_FAMILIES "^(gtest|ros|rosbag|Eigen|opencv2|tf2|tf2_ros|tf2_eigen|[a-z_]+_msgs|nodelet|pluginlib|message_filters|image_transport|cv_bridge|diagnostic_updater|octomap|ceres|boost)/|^[a-z_]+$"
  CACHE STRING "which #include <...> a PCH may hold (regex, .ci/pch.cmake)")

if(NOT COMMAND assistive_pch)
  # the workspace's first project() (catkin's toplevel) runs under old policies: IN_LIST (CMP0057)
  # needs the new one, and a function keeps the policies of where it is defined
  cmake_policy(PUSH)
  cmake_policy(SET CMP0057 NEW)
  cmake_policy(SET CMP0051 NEW)  # SOURCES lists $<TARGET_OBJECTS:..> (skipped below)
  # External headers named by FILE and, through it, by the workspace headers it includes.
  function(_assistive_pch_scan file out_var)
    set(todo "${file}")
    set(seen "")
    set(found "")
    while(todo)
      list(POP_FRONT todo f)
      if(f IN_LIST seen OR NOT EXISTS "${f}")
        continue()
      endif()
      list(APPEND seen "${f}")
      file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
      get_filename_component(dir "${f}" DIRECTORY)
      foreach(l IN LISTS lines)
        if(NOT l MATCHES "#[ \t]*include[ \t]*([<\"])([^>\"]+)[>\"]")
          continue()
        endif()
        set(h "${CMAKE_MATCH_2}")
        if(h MATCHES "^assistive_[a-z_]+/")
          # a workspace header: follow it (generated message headers do not exist here: skipped)
          string(REGEX MATCH "^[^/]+" pkg "${h}")
          list(APPEND todo "${CMAKE_SOURCE_DIR}/${pkg}/include/${h}")
        elseif(CMAKE_MATCH_1 STREQUAL "\"")
          list(APPEND todo "${dir}/${h}")
        elseif(h MATCHES "${ASSISTIVE_PCH_FAMILIES}")
          list(APPEND found "<${h}>")
        endif()
      endforeach()
    endwhile()
    set(${out_var} "${found}" PARENT_SCOPE)
  endfunction()

  # Headers of TARGET's C++ sources into out_var, the number of its translation units into n_var.
  function(_assistive_pch_target_headers target out_var n_var)
    get_target_property(srcs ${target} SOURCES)
    get_target_property(sdir ${target} SOURCE_DIR)
    get_target_property(unity ${target} UNITY_BUILD)
    set(headers "")
    set(n_alone 0)
    set(n_unity 0)
    foreach(s IN LISTS srcs)
      if(NOT s MATCHES "\\.(cpp|cc|cxx)$" OR s MATCHES "\\$<")
        continue()
      endif()
      get_filename_component(p "${s}" ABSOLUTE BASE_DIR "${sdir}")
      _assistive_pch_scan("${p}" h)
      list(APPEND headers ${h})
      get_source_file_property(skip "${p}" TARGET_DIRECTORY ${target} SKIP_UNITY_BUILD_INCLUSION)
      if(unity AND NOT skip)
        math(EXPR n_unity "${n_unity} + 1")
      else()
        math(EXPR n_alone "${n_alone} + 1")
      endif()
    endforeach()
    # CMake's unity batches hold 8 files (UNITY_BUILD_BATCH_SIZE default)
    math(EXPR n "${n_alone} + (${n_unity} + 7) / 8")
    list(REMOVE_DUPLICATES headers)
    set(${out_var} "${headers}" PARENT_SCOPE)
    set(${n_var} ${n} PARENT_SCOPE)
  endfunction()

  # What decides whether one target's PCH is valid for another: the same include folders,
  # definitions, options and libraries (whose usage requirements add more).
  function(_assistive_pch_signature target out_var)
    set(sig "")
    foreach(p INCLUDE_DIRECTORIES COMPILE_DEFINITIONS COMPILE_OPTIONS LINK_LIBRARIES)
      get_target_property(v ${target} ${p})
      string(APPEND sig "${p}=${v};")
    endforeach()
    string(MD5 sig "${sig}")
    set(${out_var} ${sig} PARENT_SCOPE)
  endfunction()

  function(assistive_pch)
    if(NOT ASSISTIVE_PCH)
      return()
    endif()
    get_property(targets DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}" PROPERTY BUILDSYSTEM_TARGETS)
    set(groups "")
    foreach(t IN LISTS targets)
      get_target_property(type ${t} TYPE)
      if(NOT type MATCHES "^(EXECUTABLE|SHARED_LIBRARY|STATIC_LIBRARY|MODULE_LIBRARY)$")
        continue()
      endif()
      _assistive_pch_target_headers(${t} headers n)
      if(NOT headers)
        continue()
      endif()
      if(t MATCHES "^test_" AND type STREQUAL "EXECUTABLE")
        # test executables of the same flags: one group, one PCH
        _assistive_pch_signature(${t} g)
        if(NOT g IN_LIST groups)
          list(APPEND groups ${g})
          set(exes_${g} "")
          set(headers_${g} "")
          set(n_${g} 0)
          set(donor_${g} "")
          set(donor_n_${g} 0)
        endif()
        list(APPEND exes_${g} ${t})
        list(APPEND headers_${g} ${headers})
        math(EXPR n_${g} "${n_${g}} + ${n}")
        if(n GREATER donor_n_${g})
          set(donor_${g} ${t})
          set(donor_n_${g} ${n})
        endif()
      elseif(NOT n LESS ASSISTIVE_PCH_MIN_UNITS)
        target_precompile_headers(${t} PRIVATE ${headers})
      endif()
    endforeach()
    foreach(g IN LISTS groups)
      if(n_${g} LESS ASSISTIVE_PCH_MIN_UNITS)
        continue()
      endif()
      list(REMOVE_DUPLICATES headers_${g})
      target_precompile_headers(${donor_${g}} PRIVATE ${headers_${g}})
      foreach(t IN LISTS exes_${g})
        if(NOT t STREQUAL donor_${g})
          target_precompile_headers(${t} REUSE_FROM ${donor_${g}})
        endif()
      endforeach()
    endforeach()
  endfunction()
  cmake_policy(POP)
endif()
cmake_language(DEFER CALL assistive_pch)
