# ps_define_module(<name> [DEPS <module>...] [PUBLIC_LIBS <target>...] [PRIVATE_LIBS <target>...]
#                  [TEST_LIBS <target>...] [WHOLE_SUITES <suite>...])
#
# Defines an OpenCV-style module from modules/<name>:
#   include/photoscene/<name>.hpp (+ include/photoscene/<name>/*.hpp)  public headers
#   src/*.cpp                                                           the library ps_<name>
#   test/*.cpp   -> ps_test_<name> (GoogleTest, every test registered with ctest)
#                   WHOLE_SUITES: fixtures whose SetUpTestSuite is expensive (a pipeline run) are
#                   registered as one ctest test <suite>.* so the set-up runs once, not per test.
#   perf/*.cpp   -> ps_perf_<name> (Google Benchmark)
# DEPS names other photoscene modules (without the ps_ prefix). Modules may be declared in any
# order; ps_check_module_graph() refuses a dependency cycle or an unknown module at the end.
#
# Installation (cmake --install): the library goes to ${CMAKE_INSTALL_LIBDIR} in the export set
# photosceneTargets as photoscene::<name> (cmake/PsInstall.cmake writes photosceneConfig.cmake),
# the public headers to ${CMAKE_INSTALL_INCLUDEDIR}. In the build tree photoscene::<name> is an
# alias of ps_<name>.

include(GNUInstallDirs)

# ps_test_binary(<target>): a GoogleTest binary's own files compile at -O1 in an optimised build:
# what they run fast is the libraries' code (-O3, unchanged); their files are parsing and
# assertions, which compiled in 27 % less time at -O1 (test_stages.cpp: 15.8 -> 11.5 s). With
# ISO C++ (no GNU extensions) GCC contracts no floating-point expression at any level, so a
# test's arithmetic gives the same numbers.
function(ps_test_binary target)
  if(CMAKE_BUILD_TYPE MATCHES "^(Release|RelWithDebInfo)$" AND NOT PS_SANITIZE)
    target_compile_options(${target} PRIVATE -O1)
  endif()
endfunction()

define_property(GLOBAL PROPERTY PS_MODULES BRIEF_DOCS "photoscene modules" FULL_DOCS "all modules")

function(ps_define_module name)
  cmake_parse_arguments(ARG "" "" "DEPS;PUBLIC_LIBS;PRIVATE_LIBS;TEST_LIBS;WHOLE_SUITES" ${ARGN})
  set(target ps_${name})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  file(GLOB_RECURSE hdrs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/include/*.hpp)
  if(NOT srcs)
    message(FATAL_ERROR "module ${name}: no sources in ${CMAKE_CURRENT_SOURCE_DIR}/src")
  endif()
  add_library(${target} STATIC ${srcs} ${hdrs})
  add_library(photoscene::${name} ALIAS ${target})
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/src>)
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  set(dep_targets)
  foreach(dep IN LISTS ARG_DEPS)
    list(APPEND dep_targets ps_${dep})
  endforeach()
  target_link_libraries(${target} PUBLIC ${dep_targets} ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  set_property(GLOBAL APPEND PROPERTY PS_MODULES ${name})
  set_property(GLOBAL PROPERTY PS_MODULE_DEPS_${name} "${ARG_DEPS}")
  install(TARGETS ${target} EXPORT photosceneTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT photoscene_dev)
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    COMPONENT photoscene_dev FILES_MATCHING PATTERN "*.hpp")

  if(PS_BUILD_TESTS)
    file(GLOB test_srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test/*.cpp)
    if(test_srcs)
      add_executable(ps_test_${name} ${test_srcs})
      target_link_libraries(ps_test_${name} PRIVATE ${target} ${ARG_TEST_LIBS} GTest::gtest GTest::gtest_main)
      target_compile_definitions(ps_test_${name} PRIVATE
        PS_SHARED_DATA_DIR="${PS_SHARED_DATA_DIR}" PS_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
        PS_BINARY_DIR="${CMAKE_BINARY_DIR}")
      ps_test_binary(ps_test_${name})
      set(filter)
      foreach(suite IN LISTS ARG_WHOLE_SUITES)
        list(APPEND filter "${suite}.*")
        add_test(NAME ${suite}.all COMMAND ps_test_${name} --gtest_filter=${suite}.*
          WORKING_DIRECTORY ${CMAKE_BINARY_DIR})
        set_tests_properties(${suite}.all PROPERTIES LABELS ${name})
      endforeach()
      if(filter)
        list(JOIN filter ":" filter)
        gtest_discover_tests(ps_test_${name} DISCOVERY_MODE PRE_TEST TEST_FILTER "-${filter}"
          WORKING_DIRECTORY ${CMAKE_BINARY_DIR} PROPERTIES LABELS ${name})
      else()
        gtest_discover_tests(ps_test_${name} DISCOVERY_MODE PRE_TEST
          WORKING_DIRECTORY ${CMAKE_BINARY_DIR} PROPERTIES LABELS ${name})
      endif()
    endif()
  endif()
  if(PS_BUILD_PERF)
    file(GLOB perf_srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/perf/*.cpp)
    if(perf_srcs)
      add_executable(ps_perf_${name} ${perf_srcs})
      target_link_libraries(ps_perf_${name} PRIVATE ${target} benchmark::benchmark benchmark::benchmark_main)
      target_compile_definitions(ps_perf_${name} PRIVATE PS_SHARED_DATA_DIR="${PS_SHARED_DATA_DIR}")
    endif()
  endif()
endfunction()

# Depth-first search over the declared module graph; a back edge is a cycle.
function(_ps_visit_module name path)
  get_property(state GLOBAL PROPERTY PS_VISIT_${name})
  if(state STREQUAL "done")
    return()
  endif()
  if(state STREQUAL "active")
    list(JOIN path " -> " chain)
    message(FATAL_ERROR "photoscene: module dependency cycle: ${chain} -> ${name}")
  endif()
  get_property(known GLOBAL PROPERTY PS_MODULES)
  if(NOT name IN_LIST known)
    list(JOIN path " -> " chain)
    message(FATAL_ERROR "photoscene: unknown module '${name}' (needed by ${chain})")
  endif()
  set_property(GLOBAL PROPERTY PS_VISIT_${name} active)
  get_property(deps GLOBAL PROPERTY PS_MODULE_DEPS_${name})
  set(next ${path})
  list(APPEND next ${name})
  foreach(dep IN LISTS deps)
    _ps_visit_module(${dep} "${next}")
  endforeach()
  set_property(GLOBAL PROPERTY PS_VISIT_${name} done)
endfunction()

function(ps_check_module_graph)
  get_property(mods GLOBAL PROPERTY PS_MODULES)
  foreach(m IN LISTS mods)
    _ps_visit_module(${m} "")
  endforeach()
  list(JOIN mods ", " all)
  message(STATUS "photoscene modules: ${all}")
endfunction()
