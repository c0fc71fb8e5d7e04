# PYTHON: the Python to install into, unless given (-DPYTHON=): the active virtual environment's ($VIRTUAL_ENV) or
# conda environment's ($CONDA_PREFIX). Included by python_install.cmake and ros2_install.cmake.
if(NOT PYTHON)
  if(DEFINED ENV{VIRTUAL_ENV})
    set(PYTHON "$ENV{VIRTUAL_ENV}/bin/python")
  elseif(DEFINED ENV{CONDA_PREFIX})
    set(PYTHON "$ENV{CONDA_PREFIX}/bin/python")
  else()
    message(FATAL_ERROR "lidarsgm: no Python environment to install into: activate one (python3 -m venv ENV && "
                        ". ENV/bin/activate) and run this again, or pass -DPYTHON=<its python>")
  endif()
endif()
if(NOT EXISTS "${PYTHON}")
  message(FATAL_ERROR "lidarsgm: ${PYTHON} does not exist")
endif()
