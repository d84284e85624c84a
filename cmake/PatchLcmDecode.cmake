# cmake -P PatchLcmDecode.cmake <header>...: hardens lcm-gen (1.3) C++ decoders against
# hostile input. The generated _decodeNoHash() resizes arrays to a length read from the
# buffer before checking that the buffer holds them (a 30-byte message can ask for ~50 GB)
# and passes negative lengths to std::vector/std::string (std::length_error). Every encoded
# element takes at least one byte and every encoded string at least its NUL, so a length
# outside [0, bytes left] (strings: [1, bytes left]) can only come from a corrupt message.
math(EXPR last "${CMAKE_ARGC} - 1")
foreach(i RANGE 3 ${last})
  set(file "${CMAKE_ARGV${i}}")
  file(READ "${file}" text)
  string(REGEX REPLACE
    "(this->[A-Za-z0-9_]+(\\[a0\\])?\\.resize\\(this->([A-Za-z0-9_]+)\\);)"
    "if(this->\\3 < 0 || this->\\3 > maxlen - pos) return -1;\n            \\1"
    text "${text}")
  string(REGEX REPLACE
    "if\\((__[A-Za-z0-9_]+_len__) > maxlen - pos\\) return -1;"
    "if(\\1 < 1 || \\1 > maxlen - pos) return -1;"
    text "${text}")
  file(WRITE "${file}" "${text}")
endforeach()
