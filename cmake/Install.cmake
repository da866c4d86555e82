# `cmake --install BUILD --prefix PREFIX`: a prefix that runs experiments without the source tree.
#   PREFIX/bin             the nodes, the tools' executables, and `dmpl` (run, sweep, report, ...)
#   PREFIX/lib             the component libraries (static)
#   PREFIX/include/dmpl    the include root: components/, sim_process/, supervisor/, tools/ and
#                          the generated message headers (dmpl/*.hpp)
#   PREFIX/share/dmpl      the data root ($DMPL_ROOT): configs/, lcmtypes/, the Python tools, the
#                          generated Python modules (python/), lcm-spy's jar (java/)
include(GNUInstallDirs)

set(DMPL_INSTALLED_EXECUTABLES
  dmpl_sim dmpl_noise dmpl_joint_player dmpl_ik dmpl_controller dmpl_supervisor
  dmpl_oneprocess dmpl_record dmpl_logcols dmpl_calibrate dmpl_hand_geometry dmpl_surface
  dmpl_link_clearance
  dmpl_bench_sim dmpl_bench_ik dmpl_bench_lcm_hop dmpl_channels_py dmpl_config)
set(DMPL_INSTALLED_LIBRARIES
  dmpl_runtime dmpl_logging dmpl_hand dmpl_kinematics dmpl_ik_core dmpl_ik_node
  dmpl_controller_core dmpl_controller_node dmpl_supervisor_core dmpl_supervisor_node
  dmpl_sim_core dmpl_sim_scheduler dmpl_sim_node dmpl_noise_core dmpl_noise_node
  dmpl_joint_trajectory dmpl_joint_player_node dmpl_calibration)
install(TARGETS ${DMPL_INSTALLED_EXECUTABLES} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${DMPL_INSTALLED_LIBRARIES} ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(PROGRAMS tools/dmpl-installed DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME dmpl)

set(DMPL_INCLUDE_ROOT ${CMAKE_INSTALL_INCLUDEDIR}/dmpl)
foreach(dir components sim_process supervisor tools/calibrate)
  get_filename_component(parent ${dir} DIRECTORY)
  install(DIRECTORY ${dir} DESTINATION ${DMPL_INCLUDE_ROOT}/${parent}
          FILES_MATCHING PATTERN "*.h" PATTERN "test" EXCLUDE)
endforeach()
install(DIRECTORY ${CMAKE_BINARY_DIR}/lcmtypes/cpp/dmpl DESTINATION ${DMPL_INCLUDE_ROOT})

set(DMPL_DATA_ROOT ${CMAKE_INSTALL_DATADIR}/dmpl)
install(DIRECTORY configs DESTINATION ${DMPL_DATA_ROOT})
install(DIRECTORY lcmtypes/ DESTINATION ${DMPL_DATA_ROOT}/lcmtypes FILES_MATCHING PATTERN "*.lcm")
install(DIRECTORY tools/python/dmpl_tools DESTINATION ${DMPL_DATA_ROOT}/tools/python
        PATTERN "__pycache__" EXCLUDE)
install(FILES tools/requirements.txt tools/requirements-bench.txt DESTINATION ${DMPL_DATA_ROOT}/tools)
install(PROGRAMS tools/spy.sh DESTINATION ${DMPL_DATA_ROOT}/tools)
install(DIRECTORY ${CMAKE_BINARY_DIR}/python/ DESTINATION ${DMPL_DATA_ROOT}/python
        PATTERN "__pycache__" EXCLUDE)
install(FILES ${CMAKE_BINARY_DIR}/java/dmpl_types.jar DESTINATION ${DMPL_DATA_ROOT}/java)
