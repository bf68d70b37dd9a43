# Install rules and the CMake package. After
#   cmake --install build --prefix P
# a consumer with P on CMAKE_PREFIX_PATH writes one of
#   find_package(clothfit 0.3 REQUIRED)                   # everything
#   find_package(clothfit REQUIRED COMPONENTS api)        # renderer API
#   find_package(clothfit REQUIRED COMPONENTS models)     # GLM only
# and links clothfit::models (header-only evaluators), clothfit::api (the
# renderer API, api/material.h, with clothfit::io: needs OpenEXR and the
# header-only nlohmann_json, no solver and no image library) or
# clothfit::clothfit (every library). Headers go to include/clothfit/<folder>/
# with the source layout; both include/ and include/clothfit/ are on the
# targets' include path, so <clothfit/models/evaluate.h> and
# "models/evaluate.h" both work.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CLOTHFIT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/clothfit)

foreach(dir models io data_synthetic holes fitting export charts bench api render)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${dir}/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/clothfit/${dir}
          FILES_MATCHING PATTERN "*.h" PATTERN "*_internal.h" EXCLUDE)
endforeach()

target_include_directories(clothfit_models INTERFACE
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/clothfit>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)

# Everything in one target (EXPORT_NAME clothfit: clothfit::clothfit).
add_library(clothfit_all INTERFACE)
set_target_properties(clothfit_all PROPERTIES EXPORT_NAME clothfit)
target_link_libraries(clothfit_all INTERFACE clothfit_models clothfit_io
  clothfit_images clothfit_synthetic clothfit_holes clothfit_fitting
  clothfit_export clothfit_charts clothfit_bench clothfit_api clothfit_render)

foreach(lib models io images synthetic holes fitting export charts bench api
    render)
  set_target_properties(clothfit_${lib} PROPERTIES EXPORT_NAME ${lib})
endforeach()

# Three export sets, one per component, each needing only the ones before.
install(TARGETS clothfit_models EXPORT clothfit_models_targets)
install(EXPORT clothfit_models_targets NAMESPACE clothfit::
        FILE clothfit-models-targets.cmake DESTINATION ${CLOTHFIT_CMAKE_DIR})
install(TARGETS clothfit_io clothfit_api EXPORT clothfit_api_targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT clothfit_api_targets NAMESPACE clothfit::
        FILE clothfit-api-targets.cmake DESTINATION ${CLOTHFIT_CMAKE_DIR})
install(TARGETS clothfit_images clothfit_synthetic clothfit_holes
          clothfit_fitting clothfit_export clothfit_charts clothfit_bench clothfit_render
          clothfit_all
        EXPORT clothfit_targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT clothfit_targets NAMESPACE clothfit::
        FILE clothfit-targets.cmake DESTINATION ${CLOTHFIT_CMAKE_DIR})
install(TARGETS clothfit clothfit-full RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${CMAKE_SOURCE_DIR}/CHANGELOG.md ${CMAKE_SOURCE_DIR}/README.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
# docs/ (formats, models, the command line, design notes, measurements and
# their pictures) beside the README, as the help and the README cite it.
install(DIRECTORY ${CMAKE_SOURCE_DIR}/docs/
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)

configure_package_config_file(
  ${CMAKE_SOURCE_DIR}/cmake/clothfit-config.cmake.in
  ${CMAKE_BINARY_DIR}/clothfit-config.cmake
  INSTALL_DESTINATION ${CLOTHFIT_CMAKE_DIR})
write_basic_package_version_file(
  ${CMAKE_BINARY_DIR}/clothfit-config-version.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/clothfit-config.cmake
              ${CMAKE_BINARY_DIR}/clothfit-config-version.cmake
        DESTINATION ${CLOTHFIT_CMAKE_DIR})
