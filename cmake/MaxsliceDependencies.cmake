# Every dependency comes from a Debian 12 package (scripts/setup.sh installs them).
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(TBB REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(Eigen3 REQUIRED NO_MODULE)
pkg_check_modules(POLYCLIPPING REQUIRED IMPORTED_TARGET polyclipping)
pkg_check_modules(LIB3MF REQUIRED IMPORTED_TARGET lib3MF)
find_package(assimp REQUIRED)
# Boost.Polygon's Voronoi diagram (header-only) for medial axes: src/geom2d/medial_axis.cpp.
find_package(Boost 1.74 REQUIRED)
# OpenVDB's narrow-band distance fields for the near-net shape (src/nearnet/, decision 0025).
# Found by hand: Debian's FindOpenVDB.cmake (beside the library, off CMake's module path) also
# demands the Boost.Iostreams headers, which only OpenVDB's delayed file loading uses.
find_path(OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)
find_library(OPENVDB_LIBRARY openvdb REQUIRED)
find_package(Imath REQUIRED CONFIG)  # OpenVDB's half float
add_library(maxslice_openvdb INTERFACE)
target_include_directories(maxslice_openvdb SYSTEM INTERFACE ${OPENVDB_INCLUDE_DIR})
target_link_libraries(maxslice_openvdb INTERFACE ${OPENVDB_LIBRARY} Imath::Imath TBB::tbb)

# Open CASCADE: linked by toolkit name so that only the toolkits maxslice uses must be
# installed (the package's CMake config also demands the visualization toolkits).
find_path(OCCT_INCLUDE_DIR Standard_Version.hxx PATH_SUFFIXES opencascade REQUIRED)
set(MAXSLICE_OCCT_TOOLKITS TKSTEP TKSTEPBase TKSTEPAttr TKSTEP209 TKIGES TKXSBase TKShHealing
    TKMesh TKTopAlgo TKGeomAlgo TKBRep TKGeomBase TKG3d TKG2d TKMath TKernel)
add_library(maxslice_occt INTERFACE)
target_include_directories(maxslice_occt SYSTEM INTERFACE ${OCCT_INCLUDE_DIR})
foreach(tk IN LISTS MAXSLICE_OCCT_TOOLKITS)
  find_library(OCCT_${tk}_LIB ${tk} REQUIRED)
  target_link_libraries(maxslice_occt INTERFACE ${OCCT_${tk}_LIB})
endforeach()

# mimalloc replaces malloc in the maxslice program (not in the libraries, whose users choose
# their own allocator): its large buffers go on transparent huge pages, which saves most of
# the page faults a job pays (docs/decisions/0018-allocator.md). The sanitizers bring their
# own allocator, so it is left out there.
option(MAXSLICE_MIMALLOC "Link the maxslice program with mimalloc" ON)
if(MAXSLICE_MIMALLOC AND NOT MAXSLICE_SANITIZE)
  find_package(mimalloc 2.0 REQUIRED CONFIG)
endif()
