# Project-wide compile flags: warnings (errors in CI) and optional sanitizers.
add_compile_options(-Wall -Wextra -Wpedantic -Wno-unused-parameter)
if(SOCC_WERROR)
  add_compile_options(-Werror)
endif()
if(SOCC_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
    # LCM's own lcm-cpp-impl.hpp casts handler objects in a way the vptr check rejects.
    -fno-sanitize=vptr)
  add_link_options(-fsanitize=address,undefined)
endif()

# Third-party headers are included as SYSTEM so their warnings do not break -Werror.
function(socc_target_warnings target)
  target_compile_options(${target} PRIVATE -Wshadow=local -Wnon-virtual-dtor)
endfunction()
