find_package(PkgConfig)

PKG_CHECK_MODULES(PC_GR_NRSAR gnuradio-nrsar)

FIND_PATH(
    GR_NRSAR_INCLUDE_DIRS
    NAMES gnuradio/nrsar/api.h
    HINTS $ENV{NRSAR_DIR}/include
        ${PC_NRSAR_INCLUDEDIR}
    PATHS ${CMAKE_INSTALL_PREFIX}/include
          /usr/local/include
          /usr/include
)

FIND_LIBRARY(
    GR_NRSAR_LIBRARIES
    NAMES gnuradio-nrsar
    HINTS $ENV{NRSAR_DIR}/lib
        ${PC_NRSAR_LIBDIR}
    PATHS ${CMAKE_INSTALL_PREFIX}/lib
          ${CMAKE_INSTALL_PREFIX}/lib64
          /usr/local/lib
          /usr/local/lib64
          /usr/lib
          /usr/lib64
          )

include("${CMAKE_CURRENT_LIST_DIR}/gnuradio-nrsarTarget.cmake")

INCLUDE(FindPackageHandleStandardArgs)
FIND_PACKAGE_HANDLE_STANDARD_ARGS(GR_NRSAR DEFAULT_MSG GR_NRSAR_LIBRARIES GR_NRSAR_INCLUDE_DIRS)
MARK_AS_ADVANCED(GR_NRSAR_LIBRARIES GR_NRSAR_INCLUDE_DIRS)
