# ctest python.install: `cmake --install` into a scratch prefix, then import the installed
# package (not the build tree's) with a fresh interpreter and step an engine.
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${PREFIX} RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
set(ENV{PYTHONPATH} ${PREFIX}/${PACKAGE_DIR})
execute_process(COMMAND ${PYTHON} -c
  "import ppohdem as pd, sys; assert pd.__file__.startswith(sys.argv[1]), pd.__file__; e = pd.Engine(pd.Scene.from_toml(sys.argv[2])); e.run(10); print('installed', pd.__file__, e.step_count)"
  ${PREFIX} ${SCENE}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed module does not import and run")
endif()
