# One precompiled header for the whole build: the third-party headers that nearly every source
# includes (OpenCV core and imgproc, Eigen, spdlog + fmt, nlohmann-json, the common standard
# headers): about 8 s per file at -O3 to parse, 1.4 s to load precompiled. Every library, test,
# benchmark, sample and the command reuse one precompiled copy, built once by the object library
# ps_pch. Most of a unity file's time is code generation, not parsing, so the saving is 10-15 %
# per file (README, "Build time").
#
# A source still includes what it uses: the precompiled header only makes those includes cheap.
# It also hides a missing standard or third-party include, as a unity batch does: configure with
# -DPS_PCH=OFF -DPS_UNITY_BUILD=OFF to compile every source on its own includes.
#
# A target whose flags or definitions differ in a way that matters (a source compiled with
# -fno-math-errno, say) falls back to parsing the headers, which -Winvalid-pch reports.

set(PS_PCH_HEADERS
  <algorithm> <array> <atomic> <cmath> <cstdint> <filesystem> <fstream> <functional> <map>
  <memory> <optional> <set> <sstream> <string> <vector>
  <opencv2/core.hpp> <opencv2/imgproc.hpp> <Eigen/Core> <Eigen/Geometry>
  <fmt/format.h> <spdlog/spdlog.h> <nlohmann/json.hpp>)

function(ps_pch_targets out dir)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    ps_pch_targets(sub_targets ${sub})
    list(APPEND targets ${sub_targets})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

function(ps_add_pch_target name)
  add_library(${name} OBJECT ${CMAKE_BINARY_DIR}/ps_pch.cpp)
  # ps_core's public third-party requirements: the include paths and definitions every consumer has
  target_link_libraries(${name} PRIVATE opencv_core opencv_imgproc Eigen3::Eigen spdlog::spdlog
                                        fmt::fmt nlohmann_json::nlohmann_json ${ARGN})
  set_target_properties(${name} PROPERTIES UNITY_BUILD OFF)
endfunction()

# ps_enable_pch(): call once, after every target is defined. Applies to ps_core and to every
# executable or library that links a photoscene module (they all get ps_core's definitions).
# The test binaries compile at -O1 (ps_test_binary) and get their own copy, built at -O1 with
# GoogleTest added: GCC keeps the optimisation level of the precompiled file's inline functions,
# so the -O3 copy made a test's file compile 20 % slower, not faster.
function(ps_enable_pch)
  # CONFIGURE writes only when the content changes, so a re-configure does not rebuild ps_pch
  file(CONFIGURE OUTPUT ${CMAKE_BINARY_DIR}/ps_pch.cpp
       CONTENT "// the translation unit that builds the precompiled header\n")
  ps_add_pch_target(ps_pch)
  target_precompile_headers(ps_pch PRIVATE ${PS_PCH_HEADERS})
  if(PS_BUILD_TESTS)
    ps_add_pch_target(ps_pch_test GTest::gtest)
    ps_test_binary(ps_pch_test)
    target_precompile_headers(ps_pch_test PRIVATE ${PS_PCH_HEADERS} <gtest/gtest.h>)
  endif()
  ps_pch_targets(targets ${CMAKE_SOURCE_DIR})
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    if(NOT type MATCHES "^(EXECUTABLE|STATIC_LIBRARY|OBJECT_LIBRARY)$" OR t MATCHES "^ps_pch")
      continue()
    endif()
    get_target_property(libs ${t} LINK_LIBRARIES)
    set(uses_core OFF)
    if(t STREQUAL "ps_core")
      set(uses_core ON)
    endif()
    foreach(l IN LISTS libs)
      if(l MATCHES "^(ps_[a-z]+|photoscene::[a-z]+)$" AND TARGET ${l})
        set(uses_core ON)
      endif()
    endforeach()
    if(NOT uses_core)
      continue()
    endif()
    get_target_property(options ${t} COMPILE_OPTIONS)
    if(TARGET ps_pch_test AND "GTest::gtest" IN_LIST libs AND "-O1" IN_LIST options)
      target_precompile_headers(${t} REUSE_FROM ps_pch_test)
    else()
      target_precompile_headers(${t} REUSE_FROM ps_pch)
    endif()
  endforeach()
endfunction()
