# Renderer engineer's part: assistive_sim_core (worlds, motion, Embree renderer; ROS-free),
# assistive_sim_bag (stereo bag reader/writer), assistive_sim_nodelet (online renderer), render_bag.

# ---- core (ROS-free)
add_library(assistive_sim_core src/world.cpp src/texture.cpp src/motion.cpp src/renderer.cpp)
target_link_libraries(assistive_sim_core ${OpenCV_LIBRARIES} ${YAML_CPP_LIBRARIES} yaml-cpp embree3)

# ---- bag I/O (used by render_bag, import_dataset and every stage's benchmark)
add_library(assistive_sim_bag src/stereo_bag.cpp src/conversions.cpp)
target_link_libraries(assistive_sim_bag ${catkin_LIBRARIES} ${OpenCV_LIBRARIES})
add_dependencies(assistive_sim_bag ${catkin_EXPORTED_TARGETS})

# ---- online renderer nodelet (glue only)
add_library(assistive_sim_nodelet src/renderer_nodelet.cpp)
target_link_libraries(assistive_sim_nodelet assistive_sim_core assistive_sim_bag ${catkin_LIBRARIES})
target_compile_definitions(assistive_sim_nodelet PRIVATE
  ASSISTIVE_SIM_SOURCE_WORLDS="${CMAKE_CURRENT_SOURCE_DIR}/worlds"
  ASSISTIVE_SIM_SHARE_WORLDS="${CMAKE_INSTALL_PREFIX}/${CATKIN_PACKAGE_SHARE_DESTINATION}/worlds")

# ---- bag generator CLI
add_executable(render_bag src/render_bag.cpp)
target_link_libraries(render_bag assistive_sim_core assistive_sim_bag)
target_compile_definitions(render_bag PRIVATE
  ASSISTIVE_SIM_SOURCE_WORLDS="${CMAKE_CURRENT_SOURCE_DIR}/worlds"
  ASSISTIVE_SIM_SHARE_WORLDS="${CMAKE_INSTALL_PREFIX}/${CATKIN_PACKAGE_SHARE_DESTINATION}/worlds")

install(TARGETS assistive_sim_core assistive_sim_bag assistive_sim_nodelet
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})
install(TARGETS render_bag RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_stereo_bag test/test_stereo_bag.cpp)
  if(TARGET test_stereo_bag)
    target_link_libraries(test_stereo_bag assistive_sim_bag)
  endif()
  foreach(t test_world test_motion)
    catkin_add_gtest(${t} test/${t}.cpp)
    if(TARGET ${t})
      target_link_libraries(${t} assistive_sim_core gtest_main)
      target_compile_definitions(${t} PRIVATE ASSISTIVE_SIM_SOURCE_WORLDS="${CMAKE_CURRENT_SOURCE_DIR}/worlds")
    endif()
  endforeach()
  catkin_add_gtest(test_renderer test/test_renderer.cpp)
  if(TARGET test_renderer)
    target_link_libraries(test_renderer assistive_sim_core assistive_sim_bag gtest_main)
    target_compile_definitions(test_renderer PRIVATE ASSISTIVE_SIM_SOURCE_WORLDS="${CMAKE_CURRENT_SOURCE_DIR}/worlds")
  endif()
  find_package(rostest REQUIRED)
  catkin_add_executable_with_gtest(test_renderer_nodelet test/test_renderer_nodelet.cpp EXCLUDE_FROM_ALL)
  if(TARGET test_renderer_nodelet)
    target_link_libraries(test_renderer_nodelet ${catkin_LIBRARIES})
    add_dependencies(test_renderer_nodelet assistive_sim_nodelet)
    add_dependencies(tests test_renderer_nodelet)
    add_rostest(test/renderer_nodelet.test DEPENDENCIES test_renderer_nodelet)
  endif()
  catkin_add_gtest(test_render_bag_cli test/test_render_bag_cli.cpp)
  if(TARGET test_render_bag_cli)
    target_link_libraries(test_render_bag_cli assistive_sim_bag gtest_main)
    target_compile_definitions(test_render_bag_cli PRIVATE RENDER_BAG_EXE="$<TARGET_FILE:render_bag>")
    add_dependencies(test_render_bag_cli render_bag)
  endif()
endif()
