# Project-wide compile flags: warnings (errors in CI) and optional sanitizers.
add_compile_options(-Wall -Wextra -Wpedantic -Wno-unused-parameter)
if(SOCC_WERROR)
  add_compile_options(-Werror)
endif()
if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # A unity build #includes the sources: GCC then reports types of one file's anonymous namespace
  # used by classes with linkage (gtest fixtures, pimpl members) that are fine per file.
  add_compile_options(-Wno-subobject-linkage)
endif()
if(SOCC_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
    # LCM's own lcm-cpp-impl.hpp casts handler objects in a way the vptr check rejects.
    -fno-sanitize=vptr)
  add_link_options(-fsanitize=address,undefined)
  # Under ASan, Eigen switches to its own aligned allocator (it no longer trusts malloc), while
  # PCL's libraries were built with malloc: a matrix allocated inside PCL and freed in our code
  # (FPFHEstimation's members) would be freed the wrong way. ASan's malloc aligns to 16 bytes,
  # as Eigen needs on x86-64, so both sides keep using malloc.
  add_compile_definitions(EIGEN_MALLOC_ALREADY_ALIGNED=1)
endif()

# Third-party headers are included as SYSTEM so their warnings do not break -Werror.
function(socc_target_warnings target)
  # -Wshadow=local is GCC's (clang, used by scripts/fuzz.sh, warns that it is unknown).
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local> -Wnon-virtual-dtor)
endfunction()

# Optional linker for -fuse-ld= (CI uses lld, Debian package lld: links several times faster
# than the default bfd). Empty: the compiler's default linker.
set(SOCC_LINKER "" CACHE STRING "Linker passed as -fuse-ld= (e.g. lld or gold); empty: default")
if(SOCC_LINKER)
  include(CheckLinkerFlag)
  check_linker_flag(CXX "-fuse-ld=${SOCC_LINKER}" SOCC_LINKER_WORKS_${SOCC_LINKER})
  if(SOCC_LINKER_WORKS_${SOCC_LINKER})
    add_link_options(-fuse-ld=${SOCC_LINKER})
  else()
    message(WARNING "SOCC_LINKER=${SOCC_LINKER}: -fuse-ld=${SOCC_LINKER} does not work; default linker")
  endif()
endif()
