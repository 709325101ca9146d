# Debian 12 packages (see README): libtbb-dev, libpolyclipping-dev, libcgal-dev, libocct-*-dev,
# lib3mf-dev, libcli11-dev, libfmt-dev, nlohmann-json3-dev.
find_package(Threads REQUIRED)
find_package(TBB REQUIRED)
find_package(fmt REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 CONFIG QUIET)
find_package(PkgConfig REQUIRED)
pkg_check_modules(POLYCLIPPING REQUIRED IMPORTED_TARGET polyclipping)
pkg_check_modules(LIB3MF REQUIRED IMPORTED_TARGET lib3MF)
pkg_check_modules(LIBZIP REQUIRED IMPORTED_TARGET libzip)
find_package(LibXml2 REQUIRED)  # reading the 3MF toolpath back (verify), its schema check in the tests
find_package(CGAL REQUIRED)
# Nesting (lamination): libnest2d-dev is header-only and declares no dependencies; it needs NLopt's
# C++ header (libnlopt-cxx-dev) and Clipper.
find_path(LIBNEST2D_INCLUDE_DIR libnest2d/libnest2d.hpp REQUIRED)
find_package(NLopt REQUIRED)
find_package(OpenCASCADE REQUIRED)
