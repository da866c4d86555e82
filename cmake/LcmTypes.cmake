# dmpl_lcmtypes(FILES ...): generate C++ headers, Python modules and a Java jar from .lcm files.
#   C++:    ${CMAKE_BINARY_DIR}/lcmtypes/cpp/dmpl/*.hpp  (INTERFACE target dmpl_lcmtypes)
#   Python: ${CMAKE_BINARY_DIR}/python/dmpl/*.py
#   Java:   ${CMAKE_BINARY_DIR}/java/dmpl_types.jar       (for lcm-spy)
function(dmpl_lcmtypes)
  cmake_parse_arguments(ARG "" "" "FILES" ${ARGN})
  set(cpp_dir ${CMAKE_BINARY_DIR}/lcmtypes/cpp)
  set(py_dir ${CMAKE_BINARY_DIR}/python)
  set(java_src ${CMAKE_BINARY_DIR}/java/src)
  set(java_cls ${CMAKE_BINARY_DIR}/java/classes)
  set(jar ${CMAKE_BINARY_DIR}/java/dmpl_types.jar)
  set(hpp_files)
  set(py_files)
  set(java_files)
  foreach(f ${ARG_FILES})
    get_filename_component(name ${f} NAME_WE)
    list(APPEND hpp_files ${cpp_dir}/dmpl/${name}.hpp)
    list(APPEND py_files ${py_dir}/dmpl/${name}.py)
    list(APPEND java_files ${java_src}/dmpl/${name}.java)
  endforeach()
  add_custom_command(
    OUTPUT ${hpp_files}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${cpp_dir}
    COMMAND ${LCM_GEN} -x --cpp-std=c++11 --cpp-hpath ${cpp_dir} ${ARG_FILES}
    COMMAND ${CMAKE_COMMAND} -DDIR=${cpp_dir}/dmpl -P ${PROJECT_SOURCE_DIR}/cmake/HardenLcmDecode.cmake
    DEPENDS ${ARG_FILES} ${PROJECT_SOURCE_DIR}/cmake/HardenLcmDecode.cmake
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "lcm-gen C++")
  add_custom_command(
    OUTPUT ${py_files} ${py_dir}/dmpl/__init__.py
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${py_dir}/dmpl
    COMMAND ${CMAKE_COMMAND} -E make_directory ${py_dir}
    COMMAND ${LCM_GEN} -p --ppath ${py_dir} ${ARG_FILES}
    DEPENDS ${ARG_FILES}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "lcm-gen Python")
  add_custom_command(
    OUTPUT ${jar}
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${java_src} ${java_cls}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${java_src} ${java_cls}
    COMMAND ${LCM_GEN} -j --jpath ${java_src} ${ARG_FILES}
    COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -cp ${LCM_JAR} -d ${java_cls} ${java_files}
    COMMAND ${Java_JAR_EXECUTABLE} cf ${jar} -C ${java_cls} .
    DEPENDS ${ARG_FILES}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "lcm-gen Java + jar")
  add_custom_target(dmpl_lcmtypes_gen ALL DEPENDS ${hpp_files} ${py_files} ${jar})
  add_library(dmpl_lcmtypes INTERFACE)
  add_dependencies(dmpl_lcmtypes dmpl_lcmtypes_gen)
  target_include_directories(dmpl_lcmtypes SYSTEM INTERFACE ${cpp_dir})
  target_link_libraries(dmpl_lcmtypes INTERFACE PkgConfig::LCM)
  set(DMPL_LCMTYPES_COUNT ${ARG_FILES} PARENT_SCOPE)
endfunction()
