# owned by the evaluation engineer: assistive_sim_eval, eval CLIs, import_dataset
# (assistive_sim_bag, the bag reader/writer, is built in render.cmake by the renderer engineer).

# ---- ROS-free evaluation core (Eigen + OpenCV): trajectories, metrics, map scoring, plots
add_library(assistive_sim_eval
  src/eval/trajectory.cpp
  src/eval/metrics.cpp
  src/eval/map_score.cpp
  src/eval/plots.cpp)
target_link_libraries(assistive_sim_eval ${OpenCV_LIBRARIES})

# ---- dataset readers for import_dataset (ROS-free: OpenCV, Eigen, yaml-cpp)
add_library(assistive_sim_import src/eval/datasets.cpp)
target_link_libraries(assistive_sim_import ${OpenCV_LIBRARIES} yaml-cpp)

install(TARGETS assistive_sim_eval assistive_sim_import
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})

# Real camera data (issue 9): by default the folder beside the workspace, <workspace>/../shared/data/real
# (the workspace is the repository root, the parent of the catkin source space CMAKE_SOURCE_DIR);
# -DASSISTIVE_REAL_DATA_DIR=... at configure time or $ASSISTIVE_REAL_DATA at run time point elsewhere.
get_filename_component(_assistive_real_data "${CMAKE_SOURCE_DIR}/../../shared/data/real" ABSOLUTE)
set(ASSISTIVE_REAL_DATA_DIR "${_assistive_real_data}" CACHE PATH "folder of the real camera data (issue 9)")
if(CATKIN_ENABLE_TESTING)
  # Real-data tests find the data there ($ASSISTIVE_REAL_DATA first) and GTEST_SKIP when it is absent.
  foreach(t test_trajectory_metrics test_map_score test_plots test_reference_numbers)
    catkin_add_gtest(${t} test/eval/${t}.cpp)
    if(TARGET ${t})
      target_link_libraries(${t} assistive_sim_eval gtest_main)
      target_compile_definitions(${t} PRIVATE ASSISTIVE_REAL_DATA_DIR="${ASSISTIVE_REAL_DATA_DIR}")
    endif()
  endforeach()
  catkin_add_gtest(test_datasets test/eval/test_datasets.cpp)
  if(TARGET test_datasets)
    target_link_libraries(test_datasets assistive_sim_import gtest_main)
    target_compile_definitions(test_datasets PRIVATE ASSISTIVE_REAL_DATA_DIR="${ASSISTIVE_REAL_DATA_DIR}")
  endif()
endif()

# ---- CLIs (rosrun assistive_sim <name>): bag glue in tools/eval_ros.cpp
add_library(assistive_sim_eval_ros STATIC tools/eval_ros.cpp)
target_link_libraries(assistive_sim_eval_ros assistive_sim_eval ${catkin_LIBRARIES})
add_dependencies(assistive_sim_eval_ros ${catkin_EXPORTED_TARGETS})
set_target_properties(assistive_sim_eval_ros PROPERTIES POSITION_INDEPENDENT_CODE ON)

add_executable(evaluate_trajectory tools/evaluate_trajectory.cpp)
target_link_libraries(evaluate_trajectory assistive_sim_eval_ros assistive_sim_eval ${catkin_LIBRARIES})
add_executable(evaluate_map tools/evaluate_map.cpp)
target_link_libraries(evaluate_map assistive_sim_eval_ros assistive_sim_eval ${catkin_LIBRARIES})
add_executable(import_dataset tools/import_dataset.cpp)
target_link_libraries(import_dataset assistive_sim_import assistive_sim_bag ${catkin_LIBRARIES} ${OpenCV_LIBRARIES})
add_dependencies(import_dataset ${catkin_EXPORTED_TARGETS})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_eval_cli test/eval/test_eval_cli.cpp)
  if(TARGET test_eval_cli)
    target_link_libraries(test_eval_cli assistive_sim_eval assistive_sim_bag ${catkin_LIBRARIES} gtest_main)
    target_compile_definitions(test_eval_cli PRIVATE ASSISTIVE_REAL_DATA_DIR="${ASSISTIVE_REAL_DATA_DIR}")
    add_dependencies(test_eval_cli evaluate_trajectory evaluate_map import_dataset)
  endif()
endif()

install(TARGETS evaluate_trajectory evaluate_map import_dataset
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
