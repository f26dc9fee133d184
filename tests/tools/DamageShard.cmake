# cmake -DFROM=<pyramid> -DTO=<copy> -DSHARD=<shard path inside it> -P DamageShard.cmake
# A copy of a pyramid with one shard file replaced by bytes that are not a shard, as a bad
# disk or a half-synced folder leaves it.
foreach(_var FROM TO SHARD)
  if(NOT DEFINED ${_var})
    message(FATAL_ERROR "DamageShard.cmake: pass -D${_var}=...")
  endif()
endforeach()
if(NOT EXISTS "${FROM}/${SHARD}")
  message(FATAL_ERROR "DamageShard.cmake: ${FROM}/${SHARD} does not exist")
endif()
file(REMOVE_RECURSE "${TO}")
file(COPY "${FROM}/" DESTINATION "${TO}")
file(WRITE "${TO}/${SHARD}" "not an OpenEXR shard\n")
