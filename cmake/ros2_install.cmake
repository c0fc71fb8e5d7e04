# Installs the ROS 2 package (ros2/lidarsgm_ros: lidarsgm_node, lidarsgm_bag, lidarsgm_kitti_to_bag) and the pinned
# ROS 2 wheels it runs on into the active virtual environment (after python_install.cmake has put cv2 there):
#
#   cmake -DREQUIREMENTS=<repo>/ros2/requirements.txt -DPACKAGE=<repo>/ros2/lidarsgm_ros -DWORK=<scratch folder> \
#         -P ros2_install.cmake
cmake_minimum_required(VERSION 3.20)
include("${CMAKE_CURRENT_LIST_DIR}/active_python.cmake")
message(STATUS "lidarsgm: installing ${REQUIREMENTS} and ${PACKAGE} for ${PYTHON}")
# setuptools writes build/ beside setup.py: build from a copy, so the checkout stays clean.
set(_copy "${WORK}/lidarsgm_ros")
file(REMOVE_RECURSE "${_copy}")
file(COPY "${PACKAGE}" DESTINATION "${WORK}" PATTERN "__pycache__" EXCLUDE)
execute_process(COMMAND "${PYTHON}" -m pip install --quiet -r "${REQUIREMENTS}" "${_copy}[bags]" RESULT_VARIABLE _rc)
file(REMOVE_RECURSE "${_copy}")
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: pip could not install ${REQUIREMENTS} (the ROS 2 wheels exist for CPython 3.10-3.13 "
                      "on x86_64 Linux) or ${PACKAGE}")
endif()
# tf2_msgs (the node's /tf and /tf_static) has no wheel: generated beside the package (ros2/tf2_msgs).
get_filename_component(_ros2 "${PACKAGE}" DIRECTORY)
execute_process(COMMAND ${CMAKE_COMMAND} -DPYTHON=${PYTHON} -DSOURCE=${_ros2}/tf2_msgs -DWORK=${WORK}
                        -P "${CMAKE_CURRENT_LIST_DIR}/tf2_msgs_install.cmake" RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: tf2_msgs could not be built into the environment (above)")
endif()
execute_process(COMMAND "${PYTHON}" -c "import cv2, rclpy, lidarsgm_ros.node; cv2.lidarsgm.StereoLidarSGM.create()"
                RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: the environment has the packages but cannot import cv2.lidarsgm, rclpy or lidarsgm_ros")
endif()
message(STATUS "lidarsgm: done; run lidarsgm_node --ros-args --params-file ..., lidarsgm_bag IN OUT, "
               "lidarsgm_kitti_to_bag DIR OUT")
