# Installs cv2 with lidarsgm (and its OpenCV libraries) into a Python environment:
#
#   cmake -DOPENCV_BUILD=<OpenCV build> -DBUILD_PYTHON=<the Python the bindings were built for> \
#         [-DPYTHON=<the environment's python>] -P python_install.cmake
#
# Without PYTHON: the active virtual environment ($VIRTUAL_ENV) or conda environment ($CONDA_PREFIX). The cv2
# package goes to the environment's site-packages, the libraries to its lib/ (their search path rewritten relative
# to themselves, so nothing else has to point there), with a dist-info, so `pip list` shows opencv-lidarsgm and
# `pip uninstall opencv-lidarsgm` removes every file again. The typing stubs OpenCV generates (cv2/lidarsgm/*.pyi)
# come with the package.
cmake_minimum_required(VERSION 3.20)

include("${CMAKE_CURRENT_LIST_DIR}/active_python.cmake")

function(py_query python code out)
  execute_process(COMMAND "${python}" -c "${code}" OUTPUT_VARIABLE _o RESULT_VARIABLE _rc
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "lidarsgm: ${python} -c \"${code}\" failed")
  endif()
  set(${out} "${_o}" PARENT_SCOPE)
endfunction()

set(_q "import sys, sysconfig; print('%d.%d' % sys.version_info[:2]); print(sys.prefix); print(sysconfig.get_paths()['platlib'])")
py_query("${PYTHON}" "${_q}" _env)
string(REPLACE "\n" ";" _env "${_env}")
list(GET _env 0 _ver)
list(GET _env 1 _prefix)
list(GET _env 2 _site)
py_query("${BUILD_PYTHON}" "import sys; print('%d.%d' % sys.version_info[:2])" _build_ver)
if(NOT _ver VERSION_EQUAL _build_ver)
  message(FATAL_ERROR "lidarsgm: the bindings were built for Python ${_build_ver}, ${PYTHON} is Python ${_ver}. "
                      "Configure a build for it (cmake -S . -B build-py${_ver} -G Ninja -DPython3_EXECUTABLE=${PYTHON}) "
                      "or use a ${_build_ver} environment")
endif()
if(NOT _site STREQUAL "${_prefix}/lib/python${_ver}/site-packages")
  message(FATAL_ERROR "lidarsgm: ${PYTHON}'s site-packages (${_site}) is not <prefix>/lib/python${_ver}/site-packages, "
                      "where OpenCV installs cv2: use a virtual environment (python3 -m venv ENV)")
endif()
py_query("${PYTHON}" "import importlib.metadata as m; print(';'.join(sorted({d.metadata['Name'] for d in m.distributions() if d.metadata['Name'] and d.metadata['Name'].lower().startswith('opencv') and d.metadata['Name'] != 'opencv-lidarsgm'})))" _other)
if(_other)
  message(FATAL_ERROR "lidarsgm: ${_prefix} already has ${_other}, whose cv2 would clash with this one: "
                      "pip uninstall ${_other}, then run this again")
endif()
execute_process(COMMAND "${PYTHON}" -c "import numpy" RESULT_VARIABLE _np OUTPUT_QUIET ERROR_QUIET)
if(NOT _np EQUAL 0)
  message(STATUS "lidarsgm: installing numpy (cv2 needs it) into ${_prefix}")
  execute_process(COMMAND "${PYTHON}" -m pip install --quiet numpy RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "lidarsgm: pip install numpy failed in ${_prefix}")
  endif()
endif()

# An earlier install of ours first goes, so that no stale file stays.
file(GLOB _old "${_site}/opencv_lidarsgm-*.dist-info")
if(_old)
  execute_process(COMMAND "${PYTHON}" -m pip uninstall --yes --quiet opencv-lidarsgm)
endif()

set(_files "")
foreach(_component libs python)
  execute_process(COMMAND "${CMAKE_COMMAND}" --install "${OPENCV_BUILD}" --prefix "${_prefix}" --component ${_component}
                  OUTPUT_QUIET RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "lidarsgm: cmake --install ${OPENCV_BUILD} --component ${_component} failed")
  endif()
  file(STRINGS "${OPENCV_BUILD}/install_manifest_${_component}.txt" _m)
  list(APPEND _files ${_m})
endforeach()

# The libraries' search path names the build's install prefix (or $ORIGIN/../lib); here they find each other relative
# to where they land.
file(STRINGS "${OPENCV_BUILD}/CMakeCache.txt" _p REGEX "^CMAKE_INSTALL_PREFIX:")
string(REGEX REPLACE "^[^=]*=" "" _build_prefix "${_p}")
foreach(_f ${_files})
  if(_f MATCHES "\\.so(\\.[0-9.]+)?$" AND NOT IS_SYMLINK "${_f}")
    get_filename_component(_dir "${_f}" DIRECTORY)
    file(RELATIVE_PATH _to_lib "${_dir}" "${_prefix}/lib")
    set(_new "$ORIGIN")
    if(_to_lib)
      set(_new "$ORIGIN/${_to_lib}")
    endif()
    file(READ_ELF "${_f}" RUNPATH _rp)
    string(REPLACE ";" ":" _rp "${_rp}")   # READ_ELF gives a CMake list
    string(REPLACE "${_build_prefix}/lib" "${_new}" _new_rp "${_rp}")
    string(REPLACE "$ORIGIN/../lib" "${_new}" _new_rp "${_new_rp}")   # the superbuild's relocatable installs
    if(NOT _new_rp STREQUAL _rp)
      file(RPATH_CHANGE FILE "${_f}" OLD_RPATH "${_rp}" NEW_RPATH "${_new_rp}")
    endif()
  endif()
endforeach()

# dist-info: pip sees the install and can remove it (RECORD lists every file, relative to site-packages).
file(STRINGS "${OPENCV_BUILD}/OpenCVConfig-version.cmake" _vl REGEX "set\\(OpenCV_VERSION ")
string(REGEX MATCH "[0-9]+\\.[0-9]+\\.[0-9]+" _version "${_vl}")
set(_info "${_site}/opencv_lidarsgm-${_version}.dist-info")
file(MAKE_DIRECTORY "${_info}")
file(WRITE "${_info}/METADATA" "Metadata-Version: 2.1\nName: opencv-lidarsgm\nVersion: ${_version}\n"
     "Summary: OpenCV ${_version} with the lidarsgm module (stereo-LiDAR fusion), installed from a lidarsgm build\n"
     "Requires-Dist: numpy\n")
file(WRITE "${_info}/INSTALLER" "lidarsgm-cmake\n")
set(_record "")
foreach(_f ${_files} "${_info}/METADATA" "${_info}/INSTALLER" "${_info}/RECORD")
  file(RELATIVE_PATH _r "${_site}" "${_f}")
  string(APPEND _record "${_r},,\n")
endforeach()
file(WRITE "${_info}/RECORD" "${_record}")

execute_process(COMMAND "${CMAKE_COMMAND}" -E env --unset=PYTHONPATH --unset=LD_LIBRARY_PATH
                        "${PYTHON}" -c "import cv2; cv2.lidarsgm.StereoLidarSGM.create(); print(cv2.__file__)"
                OUTPUT_VARIABLE _where RESULT_VARIABLE _rc OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "lidarsgm: installed, but ${PYTHON} cannot import cv2.lidarsgm")
endif()
message(STATUS "lidarsgm: cv2 ${_version} with lidarsgm installed into ${_prefix} (${_where}); "
               "pip uninstall opencv-lidarsgm removes it")
