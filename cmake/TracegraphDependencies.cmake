# Every dependency comes from Debian's packages (scripts/install-deps.sh); nothing is downloaded.
find_package(TBB REQUIRED)
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)

# Embree is only a peer to measure against and a test oracle: optional.
find_package(embree 3 QUIET)
if(embree_FOUND)
  message(STATUS "Embree ${embree_VERSION} found: peer rows in tg-bench and oracle tests enabled")
endif()
