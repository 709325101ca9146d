# Warnings are errors in the project's own code; third-party headers come in as SYSTEM includes.
function(polyaxis_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion -Werror)
endfunction()
