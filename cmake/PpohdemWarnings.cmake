# ppohdem_warnings(target): the project's warning set, applied to our own targets only
# (never to imported ones, so CGAL/Eigen headers do not flood the build).
add_library(ppohdem_warnings INTERFACE)
target_compile_options(ppohdem_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion>)
install(TARGETS ppohdem_warnings EXPORT ppohdemTargets)
