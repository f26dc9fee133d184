# cmake -DRENDER=<terrain-render> -DPYRAMID=<pyramid> -DOUT=<folder> -P RenderTelemetryTotals.cmake
# A short settled flight (terrain-render --settle --json, issue 52 item 9): its telemetry's
# totals count the streaming that settled each frame. Every load it timed was a request made
# and completed, a disk read and an upload, so those totals are at least the loads' count,
# which is not 0, and the throughput is a number above 0.
foreach(_var RENDER PYRAMID OUT)
  if(NOT DEFINED ${_var})
    message(FATAL_ERROR "RenderTelemetryTotals.cmake: pass -D${_var}=...")
  endif()
endforeach()

set(_command "${RENDER}" "${PYRAMID}" --settle --json --frames 3 --width 96 --height 64
             -o "${OUT}")
execute_process(COMMAND ${_command} RESULT_VARIABLE _status OUTPUT_VARIABLE _json
                ERROR_VARIABLE _err)
string(JOIN " " _shown ${_command})
if(NOT _status STREQUAL "0")
  message(FATAL_ERROR "${_shown}\nexited with '${_status}'\nstderr:\n${_err}")
endif()

string(JSON _loads ERROR_VARIABLE _missing GET "${_json}" telemetry load_latency_ms count)
if(_missing)
  message(FATAL_ERROR "${_shown}\nprinted no telemetry.load_latency_ms.count: ${_missing}\n"
                      "stdout:\n${_json}")
endif()
if(_loads LESS_EQUAL 0)
  message(FATAL_ERROR "${_shown}\ntimed no load (load_latency_ms.count ${_loads}): the test "
                      "needs a flight that streams")
endif()

set(_failures "")
foreach(_total requests_made requests_completed gpu_uploads)
  string(JSON _value GET "${_json}" telemetry totals ${_total})
  if(_value LESS _loads)
    string(APPEND _failures "\n  totals.${_total} ${_value} < load_latency_ms.count ${_loads}")
  endif()
endforeach()
string(JSON _bytes GET "${_json}" telemetry totals disk_read_bytes)
if(_bytes LESS_EQUAL 0)
  string(APPEND _failures "\n  totals.disk_read_bytes ${_bytes} after ${_loads} loads")
endif()
string(JSON _throughput_type TYPE "${_json}" telemetry throughput_tiles_per_s)
string(JSON _throughput GET "${_json}" telemetry throughput_tiles_per_s)
if(NOT _throughput_type STREQUAL "NUMBER" OR NOT _throughput GREATER 0)
  string(APPEND _failures "\n  throughput_tiles_per_s ${_throughput} after ${_loads} loads")
endif()
if(_failures)
  message(FATAL_ERROR "${_shown}\ntelemetry totals miss the streaming it timed:${_failures}")
endif()
message(STATUS "${_loads} loads; the totals count them")
