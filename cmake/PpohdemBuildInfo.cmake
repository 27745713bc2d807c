# Provenance baked into the binary (CoMD's generate_info_header): version, git hash,
# compiler and flags. Printed at the top of every run and written into every output header.
find_package(Git QUIET)
set(PPOHDEM_GIT_HASH "unknown")
if(GIT_FOUND AND EXISTS ${CMAKE_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE _hash
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE _rc)
  if(_rc EQUAL 0 AND _hash)
    set(PPOHDEM_GIT_HASH ${_hash})
  endif()
  # Re-configure when HEAD moves (a commit, a checkout), so an incremental build never reports
  # a stale hash: depend on HEAD, the branch's ref file and packed-refs.
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --absolute-git-dir
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE _git_dir
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  execute_process(COMMAND ${GIT_EXECUTABLE} symbolic-ref -q HEAD
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE _git_ref
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(_git_dir)
    set(_git_files ${_git_dir}/HEAD)
    if(_git_ref AND EXISTS ${_git_dir}/${_git_ref})
      list(APPEND _git_files ${_git_dir}/${_git_ref})
    endif()
    if(EXISTS ${_git_dir}/packed-refs)
      list(APPEND _git_files ${_git_dir}/packed-refs)
    endif()
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_git_files})
  endif()
endif()
string(TOUPPER "${CMAKE_BUILD_TYPE}" _bt)
set(PPOHDEM_CXX_FLAGS "${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${_bt}}")
string(STRIP "${PPOHDEM_CXX_FLAGS}" PPOHDEM_CXX_FLAGS)
foreach(_opt MPI OPENMP)
  if(PPOHDEM_ENABLE_${_opt})
    set(PPOHDEM_ENABLE_${_opt}_BOOL true)
  else()
    set(PPOHDEM_ENABLE_${_opt}_BOOL false)
  endif()
endforeach()
configure_file(${CMAKE_SOURCE_DIR}/cmake/build_info.hpp.in
  ${CMAKE_BINARY_DIR}/generated/ppohdem/build_info.hpp @ONLY)
