# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later

# ctest installed_headers: installs the nrsar_headers component into PREFIX (inside the build
# tree, never the system) and fails when a header under SOURCE_DIR/include is not installed
# at the same place.
# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DPREFIX=... -P check_installed_headers.cmake
file(REMOVE_RECURSE ${PREFIX})
execute_process(
    COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --component nrsar_headers
    RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cmake --install --component nrsar_headers failed (${rc})")
endif()
file(GLOB_RECURSE source_headers RELATIVE ${SOURCE_DIR}/include ${SOURCE_DIR}/include/*.h)
file(GLOB_RECURSE installed RELATIVE ${PREFIX}/include ${PREFIX}/include/*.h)
set(missing ${source_headers})
if(installed)
    list(REMOVE_ITEM missing ${installed})
endif()
list(LENGTH source_headers n)
if(missing)
    string(REPLACE ";" "\n  " missing "${missing}")
    message(FATAL_ERROR "public headers not installed (add them to the install rules of "
                        "include/gnuradio/nrsar/CMakeLists.txt):\n  ${missing}")
endif()
message(STATUS "all ${n} public headers installed")
