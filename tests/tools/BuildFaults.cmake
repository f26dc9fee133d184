# cmake -DBUILD=<terrain-build> -DOUT=<folder for the outputs> -DCASE=disk_full|killed|read_only
#       -P BuildFaults.cmake
# terrain-build when the machine fails it, as a user would meet it:
#  disk_full  the disk fills during the build (a file size limit with SIGXFSZ ignored makes
#             write(2) fail with EFBIG, as a full disk fails with ENOSPC): exit status 1, a
#             message naming the shard, and nothing left that looks like a pyramid;
#  killed     kill -9 at points spread over the build: the output path never holds a
#             manifest.json unless the build finished (then it is the whole pyramid);
#  read_only  an output folder that cannot be written: exit status 1 naming it, nothing left.
foreach(_var BUILD OUT CASE)
  if(NOT DEFINED ${_var})
    message(FATAL_ERROR "BuildFaults.cmake: pass -D${_var}=...")
  endif()
endforeach()
set(_source "procedural:size=2049,seed=5")
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
set(_pyramid "${OUT}/faulted.pyramid")

# Nothing at the output path and no partial folder holding a manifest.
function(expect_nothing_left why)
  if(EXISTS "${_pyramid}")
    message(FATAL_ERROR "${why}: ${_pyramid} exists")
  endif()
  file(GLOB _manifests "${OUT}/*/manifest.json")
  if(_manifests)
    message(FATAL_ERROR "${why}: a manifest was left behind: ${_manifests}")
  endif()
endfunction()

if(CASE STREQUAL "disk_full")
  # 256 blocks of 512 bytes (dash's unit): the first 1 MiB shard cannot be written.
  execute_process(
    COMMAND sh -c "trap '' XFSZ; ulimit -f 256; exec \"$0\" \"$@\"" "${BUILD}" "${_source}"
            -o "${_pyramid}"
    RESULT_VARIABLE _status OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
  if(NOT _status EQUAL 1)
    message(FATAL_ERROR "a full disk: exit status '${_status}', expected 1\n${_err}")
  endif()
  # The file being written: a shard, or the temporary raster of a level.
  if(NOT _err MATCHES "faulted\\.pyramid[^:\n]*/[^:\n/]+: cannot write[^\n]*File too large")
    message(FATAL_ERROR "a full disk: the message does not name the file:\n${_err}")
  endif()
  expect_nothing_left("a full disk")
elseif(CASE STREQUAL "killed")
  # How long a whole build takes here, then kills at 5 %, 20 %, ... 95 % of it. A quarter
  # of the size of the other cases: nine builds (one timed, eight killed) stay short in the
  # sanitizer builds, and a 1025² build still writes several shards and levels.
  set(_source "procedural:size=1025,seed=5")
  string(TIMESTAMP _start "%s%f")
  execute_process(COMMAND "${BUILD}" "${_source}" -o "${OUT}/timed.pyramid"
                  RESULT_VARIABLE _status OUTPUT_QUIET ERROR_VARIABLE _err)
  string(TIMESTAMP _end "%s%f")
  if(NOT _status EQUAL 0)
    message(FATAL_ERROR "the build to time failed: ${_err}")
  endif()
  math(EXPR _whole_ms "(${_end} - ${_start}) / 1000")
  file(REMOVE_RECURSE "${OUT}/timed.pyramid")
  foreach(_percent 5 20 35 50 65 80 95 110)
    math(EXPR _after_ms "${_whole_ms} * ${_percent} / 100 + 1")
    if(_after_ms LESS 1000)
      set(_after "0.${_after_ms}")
      string(REGEX REPLACE "^0\\.([0-9])$" "0.00\\1" _after "${_after}")
      string(REGEX REPLACE "^0\\.([0-9][0-9])$" "0.0\\1" _after "${_after}")
    else()
      math(EXPR _seconds "${_after_ms} / 1000")
      math(EXPR _millis "${_after_ms} % 1000 + 1000")
      string(SUBSTRING "${_millis}" 1 3 _millis)
      set(_after "${_seconds}.${_millis}")
    endif()
    file(REMOVE_RECURSE "${_pyramid}")
    execute_process(COMMAND timeout -s KILL ${_after} "${BUILD}" "${_source}" -o "${_pyramid}"
                    RESULT_VARIABLE _status OUTPUT_QUIET ERROR_QUIET)
    message(STATUS "killed after ${_after} s (${_percent} % of ${_whole_ms} ms): status ${_status}")
    if(_status EQUAL 0)
      if(NOT EXISTS "${_pyramid}/manifest.json")
        message(FATAL_ERROR "a finished build left no manifest")
      endif()
    elseif(_status EQUAL 137 OR _status STREQUAL "Subprocess killed")
      # Killed after the final rename (while exiting) leaves the whole pyramid: fine. What
      # must never be there is a pyramid path without its manifest.
      if(EXISTS "${_pyramid}" AND NOT EXISTS "${_pyramid}/manifest.json")
        message(FATAL_ERROR "killed after ${_after} s, the build left ${_pyramid} without a manifest")
      endif()
      file(GLOB _partials "${OUT}/faulted.pyramid.partial-*")
      if(_partials)  # what kill -9 leaves: named partial, never a pyramid
        file(REMOVE_RECURSE ${_partials})
      endif()
    else()
      message(FATAL_ERROR "killed after ${_after} s: unexpected status '${_status}'")
    endif()
  endforeach()
elseif(CASE STREQUAL "read_only")
  # Permissions do not stop root: there the folder is /sys, which nobody may write.
  execute_process(COMMAND id -u OUTPUT_VARIABLE _uid OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(_locked "${OUT}/locked")
  if(_uid STREQUAL "0")
    set(_locked "/sys")
  else()
    file(MAKE_DIRECTORY "${_locked}")
    file(CHMOD "${_locked}" DIRECTORY_PERMISSIONS OWNER_READ OWNER_EXECUTE)
  endif()
  execute_process(COMMAND "${BUILD}" "${_source}" -o "${_locked}/faulted.pyramid"
                  RESULT_VARIABLE _status OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
  if(NOT _uid STREQUAL "0")
    file(CHMOD "${_locked}" DIRECTORY_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
    file(GLOB _left "${_locked}/*")
    if(_left)
      message(FATAL_ERROR "a read-only folder: left ${_left}")
    endif()
  endif()
  if(NOT _status EQUAL 1)
    message(FATAL_ERROR "a read-only folder: exit status '${_status}', expected 1\n${_err}")
  endif()
  if(NOT _err MATCHES "faulted\\.pyramid[^\n]*: cannot create")
    message(FATAL_ERROR "a read-only folder: the message does not name the output:\n${_err}")
  endif()
else()
  message(FATAL_ERROR "BuildFaults.cmake: unknown CASE '${CASE}'")
endif()
