# One place for compiler flags: -Wall -Wextra everywhere, warnings as errors with STICKSLIP_WERROR (developers, CI),
# optional sanitizers.
# -Wformat-truncation is off: every snprintf is bounded and truncating an over-long name is intended.
set(STICKSLIP_C_WARNINGS -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wno-unused-parameter
    -Wno-format-truncation)
set(STICKSLIP_CXX_WARNINGS -Wall -Wextra)
if(STICKSLIP_WERROR)
  list(APPEND STICKSLIP_C_WARNINGS -Werror)
  list(APPEND STICKSLIP_CXX_WARNINGS -Werror)
endif()

if(STICKSLIP_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# stickslip_warnings(target): applies the project's warning set to a C or C++ target.
function(stickslip_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:C>:${STICKSLIP_C_WARNINGS}>
    $<$<COMPILE_LANGUAGE:CXX>:${STICKSLIP_CXX_WARNINGS}>)
endfunction()
