# cmake -DOPENCV_BUILD=<OpenCV build dir> -DWORK=<scratch dir> -DSRC=<this folder> -P run_install_test.cmake
# Installs the OpenCV build (with lidarsgm) into WORK/prefix, builds the consumer project against it with
# find_package(OpenCV REQUIRED lidarsgm), and runs it.
file(REMOVE_RECURSE "${WORK}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${OPENCV_BUILD}" --prefix "${WORK}/prefix"
                OUTPUT_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "install failed (${rc})")
endif()
file(GLOB_RECURSE cfg "${WORK}/prefix/*/OpenCVConfig.cmake")
list(GET cfg 0 cfg)
get_filename_component(cfg_dir "${cfg}" DIRECTORY)
message(STATUS "installed OpenCVConfig.cmake: ${cfg}")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SRC}" -B "${WORK}/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release
                        "-DOpenCV_DIR=${cfg_dir}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the consumer project failed (${rc})")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK}/consumer" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the consumer project failed (${rc})")
endif()
execute_process(COMMAND "${WORK}/consumer/lidarsgm_consumer" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the consumer program failed (${rc})")
endif()
