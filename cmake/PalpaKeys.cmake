# Ed25519 keys in the build: which public keys the board's firmware trusts (compiled in, never
# taken from the link) and which private key the build signs its own images with. The defaults
# are the DEVELOPMENT ONLY pair in firmware/keys/; a lab builds with its own (docs/flashing.md):
#   cmake --preset mps2 -DPALPA_TRUSTED_KEYS=/keys/lab.pub -DPALPA_SIGNING_KEY=/keys/lab.key
set(PALPA_TRUSTED_KEYS "${PROJECT_SOURCE_DIR}/firmware/keys/development.pub;${PROJECT_SOURCE_DIR}/firmware/keys/development-next.pub"
    CACHE STRING "Public key files the firmware trusts: the current key, and at most one to rotate to")
set(PALPA_SIGNING_KEY "${PROJECT_SOURCE_DIR}/firmware/keys/development.key"
    CACHE FILEPATH "Private key file the build signs its firmware images with")

# palpa_read_key(OUT FILE) -> the key's 64 hex digits: '#' lines are comments, one line of hex.
function(palpa_read_key out file)
  if(NOT EXISTS "${file}")
    message(FATAL_ERROR "key file ${file} does not exist")
  endif()
  file(STRINGS "${file}" lines)
  set(hex "")
  foreach(line IN LISTS lines)
    string(STRIP "${line}" line)
    if(line STREQUAL "" OR line MATCHES "^#")
      continue()
    endif()
    if(NOT hex STREQUAL "" OR NOT line MATCHES "^[0-9a-fA-F]+$")
      message(FATAL_ERROR "${file}: expected one line of 64 hexadecimal digits (and '#' comments)")
    endif()
    set(hex "${line}")
  endforeach()
  string(LENGTH "${hex}" length)
  if(NOT length EQUAL 64)
    message(FATAL_ERROR "${file}: expected 64 hexadecimal digits (32 bytes), found ${length}")
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${file}")
  string(TOLOWER "${hex}" hex)
  set(${out} "${hex}" PARENT_SCOPE)
endfunction()

# palpa_key_initializer(OUT FILE) -> "0x.., 0x.., ..." (32 bytes) for a C++ array.
function(palpa_key_initializer out file)
  palpa_read_key(hex "${file}")
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1, " bytes "${hex}")
  set(${out} "${bytes}" PARENT_SCOPE)
endfunction()
