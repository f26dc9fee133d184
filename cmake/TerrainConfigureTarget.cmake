# terrain_configure_target(<target>): C++20, the house warning set, warnings as errors
# when TERRAIN_WARNINGS_AS_ERRORS is on, and the sanitizers named in TERRAIN_SANITIZER.
# Every target of the project goes through this one function (../shared/STYLE.md).

# Compare with ',' for ';': a list inside a list would be flattened into its elements.
string(REPLACE ";" "," _terrain_sanitizer_key "${TERRAIN_SANITIZER}")
set(_terrain_sanitizers_ok "" "address,undefined" "undefined,address" "address" "undefined" "thread")
if(NOT _terrain_sanitizer_key IN_LIST _terrain_sanitizers_ok)
  message(FATAL_ERROR "TERRAIN_SANITIZER='${TERRAIN_SANITIZER}': use '', 'address;undefined' or 'thread'")
endif()

# A fuzzing build instruments every target for libFuzzer's coverage, under ASan and UBSan.
if(TERRAIN_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "TERRAIN_FUZZ needs clang (libFuzzer): configure with CXX=clang++ (scripts/fuzz.sh)")
  endif()
  if(NOT _terrain_sanitizer_key STREQUAL "address,undefined")
    message(FATAL_ERROR "TERRAIN_FUZZ runs under ASan and UBSan: set TERRAIN_SANITIZER='address;undefined'")
  endif()
endif()

function(terrain_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion>)
  if(TERRAIN_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-Werror>)
  endif()
  # A unity build #includes each .cpp into a batch file, and GCC then takes a class whose
  # member has a type from the .cpp's anonymous namespace (a pimpl's Impl) for one defined in
  # a header: -Wsubobject-linkage, a false alarm there.
  if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-Wno-subobject-linkage>)
  endif()
  if(TERRAIN_SANITIZER)
    string(REPLACE ";" "," _list "${TERRAIN_SANITIZER}")
    target_compile_options(${target} PRIVATE -fsanitize=${_list} -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PUBLIC -fsanitize=${_list})
  endif()
  if(TERRAIN_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
