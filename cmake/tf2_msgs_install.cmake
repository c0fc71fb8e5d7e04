# Generates and installs the typesupport of ros2/tf2_msgs (TFMessage, the message of /tf and /tf_static) into a
# Python environment that has the ROS 2 wheels of ros2/requirements.txt (its build side included):
#
#   cmake -DPYTHON=<env>/bin/python -DSOURCE=<repo>/ros2/tf2_msgs -DWORK=<scratch folder> -P tf2_msgs_install.cmake
#
# The wheels install a ROS prefix into the environment (<env>/share, <env>/lib): tf2_msgs is built against it with
# plain CMake and installed into it, where rclpy finds it with the other messages.
cmake_minimum_required(VERSION 3.20)
execute_process(COMMAND "${PYTHON}" -c "import sys; print(sys.prefix)" OUTPUT_VARIABLE _prefix
                OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: ${PYTHON} does not run")
endif()
get_filename_component(_bin "${PYTHON}" DIRECTORY)
set(_build "${WORK}/tf2_msgs_build")
file(REMOVE_RECURSE "${_build}")
set(_env ${CMAKE_COMMAND} -E env "PATH=${_bin}:$ENV{PATH}")
execute_process(COMMAND ${_env} ${CMAKE_COMMAND} -S "${SOURCE}" -B "${_build}" -DCMAKE_BUILD_TYPE=Release
                        "-DCMAKE_PREFIX_PATH=${_prefix}" "-DCMAKE_INSTALL_PREFIX=${_prefix}"
                        "-DPython3_EXECUTABLE=${PYTHON}" -DBUILD_TESTING=OFF
                OUTPUT_QUIET RESULT_VARIABLE _rc)
if(_rc EQUAL 0)
  execute_process(COMMAND ${_env} ${CMAKE_COMMAND} --build "${_build}" OUTPUT_QUIET RESULT_VARIABLE _rc)
endif()
if(_rc EQUAL 0)
  execute_process(COMMAND ${CMAKE_COMMAND} --install "${_build}" OUTPUT_QUIET RESULT_VARIABLE _rc)
endif()
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: building tf2_msgs (${SOURCE}) into ${_prefix} failed; its build folder is ${_build}")
endif()
execute_process(COMMAND "${PYTHON}" -c "from tf2_msgs.msg import TFMessage; TFMessage()" RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: tf2_msgs was installed into ${_prefix} but does not import")
endif()
file(REMOVE_RECURSE "${_build}")
message(STATUS "lidarsgm: tf2_msgs installed into ${_prefix}")
