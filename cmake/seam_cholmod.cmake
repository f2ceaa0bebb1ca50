# CHOLMOD (SuiteSparse) ships no CMake config on Debian bookworm: find its header and library.
# METIS (Debian's libmetis-dev; CHOLMOD itself links libmetis5): the nested dissection orders
# are computed by METIS_NodeND directly, with options CHOLMOD's wrapper does not pass.
# Defines the interface target seam_cholmod. Included by the top CMakeLists.txt and by the
# standalone fuzz project (tests/fuzz).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
add_library(seam_cholmod INTERFACE)
target_include_directories(seam_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR} ${METIS_INCLUDE_DIR})
target_link_libraries(seam_cholmod INTERFACE ${CHOLMOD_LIBRARY} ${METIS_LIBRARY})
