# One place for the project's compiler warnings.
function(semloc_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                                           -Wnon-virtual-dtor -Wno-psabi)
endfunction()
