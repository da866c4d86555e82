# Every external dependency, found once. Their traps on Debian 12: docs/dependencies.md.
find_package(PkgConfig REQUIRED)
# LCM 1.3.1 ships no CMake config; its pkg-config file needs glib.
pkg_check_modules(LCM REQUIRED IMPORTED_TARGET lcm)
# Bullet's CMake config is broken on Debian (missing library, relative include path).
pkg_check_modules(BULLET REQUIRED IMPORTED_TARGET bullet-float64)  # PyBullet is double too
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(orocos_kdl REQUIRED)
add_library(dmpl_orocos_kdl INTERFACE)
target_include_directories(dmpl_orocos_kdl SYSTEM INTERFACE ${orocos_kdl_INCLUDE_DIRS})
target_link_libraries(dmpl_orocos_kdl INTERFACE ${orocos_kdl_LIBRARIES} Eigen3::Eigen)
find_package(urdfdom REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(spdlog REQUIRED)
# Header-only: every executable's command line (components/runtime/command_line.h).
find_package(CLI11 CONFIG REQUIRED)
find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
find_package(Threads REQUIRED)
# Ceres is for the offline calibration tool only (a TU with Ceres costs ~7 s / 450 MB to compile).
find_package(Ceres 2.1 REQUIRED)
# GLPK (libglpk-dev) ships neither a CMake config nor a pkg-config file.
find_path(GLPK_INCLUDE_DIR glpk.h REQUIRED)
find_library(GLPK_LIBRARY glpk REQUIRED)
add_library(GLPK::GLPK UNKNOWN IMPORTED)
set_target_properties(GLPK::GLPK PROPERTIES IMPORTED_LOCATION ${GLPK_LIBRARY}
                                            INTERFACE_INCLUDE_DIRECTORIES ${GLPK_INCLUDE_DIR})

find_program(LCM_GEN lcm-gen REQUIRED)
find_package(Java COMPONENTS Development REQUIRED)
find_file(LCM_JAR lcm.jar PATHS /usr/share/java REQUIRED)

# dmpl_add_gtest(NAME src... LIBS lib... [LABELS label...]): a gtest executable registered with
# ctest per test case (label `unit` unless told otherwise).
include(GoogleTest)
function(dmpl_add_gtest name)
  cmake_parse_arguments(ARG "" "" "LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_UNPARSED_ARGUMENTS})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE DMPL_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                             DMPL_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  gtest_discover_tests(${name} PROPERTIES LABELS "${ARG_LABELS}" DISCOVERY_TIMEOUT 30)
endfunction()
