# cmake -DDIR=build/lcmtypes/cpp/dmpl -P HardenLcmDecode.cmake
# lcm-gen 1.3/1.4's C++ decode of a string trusts its length prefix when it is negative: it
# checks only `len > maxlen - pos`, then assigns `len - 1` bytes, which for INT_MIN overflows to
# 2^31 - 1 and reads far past the packet (tests/fuzz/decode_fuzz_test.cc found it). Every
# generated check is made to refuse lengths below 1 as well; a header whose strings are decoded
# some other way stops the build, so that a new lcm-gen is looked at again.
cmake_minimum_required(VERSION 3.16)
file(GLOB headers ${DIR}/*.hpp)
foreach(f ${headers})
  file(READ ${f} text)
  string(REGEX MATCHALL "\\.assign\\(" decodes "${text}")
  string(REGEX REPLACE "if\\((__[a-z_]+) > maxlen - pos\\) return -1;"
                       "if(\\1 < 1 || \\1 > maxlen - pos) return -1;" hardened "${text}")
  string(REGEX MATCHALL "< 1 [|][|] __[a-z_]+ > maxlen - pos" checks "${hardened}")
  list(LENGTH decodes n_decodes)
  list(LENGTH checks n_checks)
  if(NOT n_decodes EQUAL n_checks)
    message(FATAL_ERROR "${f}: ${n_decodes} string decodes but ${n_checks} hardened length "
                        "checks: lcm-gen's output changed; see cmake/HardenLcmDecode.cmake")
  endif()
  if(NOT hardened STREQUAL text)
    file(WRITE ${f} "${hardened}")
  endif()
endforeach()
