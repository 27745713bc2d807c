# The Python module's dependencies (bindings/python, docs/python.md): pybind11 and NumPy for the
# system interpreter /usr/bin/python3 (the `python3` first on PATH may be another one without
# NumPy). Sets PPOHDEM_PYTHON_FOUND. Override the interpreter with -DPython_EXECUTABLE=...
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Interpreter the Python module is built for")
endif()
find_package(Python 3.8 COMPONENTS Interpreter Development.Module NumPy QUIET)
set(PYBIND11_FINDPYTHON ON)
find_package(pybind11 CONFIG QUIET)
if(Python_FOUND AND Python_NumPy_FOUND AND pybind11_FOUND)
  set(PPOHDEM_PYTHON_FOUND ON)
else()
  set(PPOHDEM_PYTHON_FOUND OFF)
endif()
