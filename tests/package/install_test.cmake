# ctest package_install (issue 21): the library as an outside program uses it.
#
#  1. cmake --install the build tree into a staging prefix, then move the prefix elsewhere (the
#     installed package must be relocatable) and check that no installed CMake file names the
#     source or the build tree;
#  2. configure and build examples/cad_exporter (copied out of the source tree) against it with
#     only CMAKE_PREFIX_PATH pointing at the prefix; check that quadcage was found there and that no
#     compile command reaches into the source tree;
#  3. run the example on data/eight.off and the installed `quadcage fit --level LEVEL` on the same
#     mesh, and let check_cad_exporter.py compare what they printed and wrote.
#
# Skipped (prints "package_install: SKIPPED: <why>") only when a tool it needs is missing; with the
# environment variable CI set (not 0/false) that is a failure instead.
#
# Variables: QC_SOURCE_DIR, QC_BUILD_DIR, QC_WORK_DIR, QC_CXX_COMPILER, QC_GENERATOR, QC_CONFIG,
# QC_PYTHON, QC_LEVEL.
cmake_minimum_required(VERSION 3.20)

foreach(v QC_SOURCE_DIR QC_BUILD_DIR QC_WORK_DIR QC_CXX_COMPILER QC_GENERATOR QC_PYTHON QC_LEVEL)
  if(NOT DEFINED ${v} OR "${${v}}" STREQUAL "")
    message(FATAL_ERROR "package_install: ${v} is not set")
  endif()
endforeach()

function(skip_or_fail why)
  if(DEFINED ENV{CI} AND NOT "$ENV{CI}" MATCHES "^(|0|false|FALSE|False|no|NO)$")
    message(FATAL_ERROR "package_install: ${why} (CI=$ENV{CI}: this test must run in CI)")
  endif()
  message("package_install: SKIPPED: ${why}")
endfunction()

# --- what the test needs besides the build tree --------------------------------------------------
if(NOT EXISTS "${QC_CXX_COMPILER}")
  skip_or_fail("no C++ compiler at '${QC_CXX_COMPILER}' to build the example with")
  return()
endif()
execute_process(COMMAND "${QC_PYTHON}" -c "import numpy, scipy.spatial"
  RESULT_VARIABLE py_rc OUTPUT_QUIET ERROR_QUIET)
if(NOT py_rc EQUAL 0)
  skip_or_fail("${QC_PYTHON} cannot import numpy and scipy (Debian: python3-numpy python3-scipy)")
  return()
endif()

# Runs a command; on failure stops the test with its output. Output in <out_var> if given.
function(step name)
  cmake_parse_arguments(S "" "OUTPUT;WORKING_DIRECTORY" "COMMAND" ${ARGN})
  if(NOT S_WORKING_DIRECTORY)
    set(S_WORKING_DIRECTORY "${QC_WORK_DIR}")
  endif()
  string(TIMESTAMP t0 "%s")
  execute_process(COMMAND ${S_COMMAND} WORKING_DIRECTORY "${S_WORKING_DIRECTORY}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(TIMESTAMP t1 "%s")
  math(EXPR dt "${t1} - ${t0}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "package_install: ${name} failed (${rc}):\n  ${S_COMMAND}\n--- stdout\n${out}\n--- stderr\n${err}")
  endif()
  message("package_install: ${name}: ok (${dt} s)")
  if(S_OUTPUT)
    set(${S_OUTPUT} "${out}" PARENT_SCOPE)
  endif()
endfunction()

file(REMOVE_RECURSE "${QC_WORK_DIR}")
file(MAKE_DIRECTORY "${QC_WORK_DIR}")
set(stage "${QC_WORK_DIR}/stage")
set(prefix "${QC_WORK_DIR}/prefix")

# --- 1. install, relocate ------------------------------------------------------------------------
set(config_args)
if(QC_CONFIG)
  set(config_args --config "${QC_CONFIG}")
endif()
step("install" COMMAND "${CMAKE_COMMAND}" --install "${QC_BUILD_DIR}" --prefix "${stage}" ${config_args})
file(RENAME "${stage}" "${prefix}")

file(GLOB_RECURSE package_files "${prefix}/*.cmake")
foreach(f IN LISTS package_files)
  file(READ "${f}" text)
  foreach(tree "${QC_SOURCE_DIR}" "${QC_BUILD_DIR}" "${stage}")
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "package_install: ${f} names ${tree}: the installed package is not relocatable")
    endif()
  endforeach()
endforeach()
foreach(f bin/quadcage share/quadcage/quadriflow.py include/quadcage/fit/fit.h)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "package_install: ${prefix}/${f} was not installed")
  endif()
endforeach()
file(GLOB config "${prefix}/lib*/cmake/quadcage/quadcageConfig.cmake" "${prefix}/lib*/*/cmake/quadcage/quadcageConfig.cmake")
if(NOT config)
  message(FATAL_ERROR "package_install: no quadcageConfig.cmake under ${prefix}")
endif()
get_filename_component(config_dir "${config}" DIRECTORY)

# --- 2. the example, outside the source tree -----------------------------------------------------
set(example_src "${QC_WORK_DIR}/cad_exporter")
set(example_build "${QC_WORK_DIR}/cad_exporter-build")
file(COPY "${QC_SOURCE_DIR}/examples/cad_exporter/" DESTINATION "${example_src}")
step("configure the example" COMMAND "${CMAKE_COMMAND}" -S "${example_src}" -B "${example_build}"
  -G "${QC_GENERATOR}" -DCMAKE_CXX_COMPILER=${QC_CXX_COMPILER}
  "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
file(STRINGS "${example_build}/CMakeCache.txt" found REGEX "^quadcage_DIR:")
if(NOT found STREQUAL "quadcage_DIR:PATH=${config_dir}")
  message(FATAL_ERROR "package_install: the example found '${found}', not ${config_dir}")
endif()
step("build the example" COMMAND "${CMAKE_COMMAND}" --build "${example_build}" -j2 ${config_args})
file(READ "${example_build}/compile_commands.json" commands)
foreach(tree include src tools examples)
  string(FIND "${commands}" "${QC_SOURCE_DIR}/${tree}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "package_install: the example's compile commands reach into ${QC_SOURCE_DIR}/${tree}:\n${commands}")
  endif()
endforeach()
string(FIND "${commands}" "${prefix}/include" at)
if(at EQUAL -1)
  message(FATAL_ERROR "package_install: the example does not compile against ${prefix}/include:\n${commands}")
endif()
set(exe "${example_build}/cad_exporter")
if(QC_CONFIG AND NOT EXISTS "${exe}")
  set(exe "${example_build}/${QC_CONFIG}/cad_exporter")  # multi-config generators
endif()

# --- 3. run both, compare ------------------------------------------------------------------------
set(mesh "${QC_SOURCE_DIR}/data/eight.off")
step("cad_exporter eight.off" OUTPUT example_stdout
  COMMAND "${exe}" "${mesh}" "${QC_WORK_DIR}/example-out" "${QC_LEVEL}")
file(WRITE "${QC_WORK_DIR}/example-stdout.txt" "${example_stdout}")
message("${example_stdout}")
# limit.ply within 5e-5 of the diagonal of the limit surface everywhere measured, so that exact limit
# points can be checked against it at the issue's 1e-4.
step("installed quadcage fit eight.off --level ${QC_LEVEL}"
  COMMAND "${prefix}/bin/quadcage" fit "${mesh}" --level "${QC_LEVEL}" --limit-max-error 5e-5 -o "${QC_WORK_DIR}/cli-fit" -q)
step("check" OUTPUT check_stdout
  COMMAND "${QC_PYTHON}" "${CMAKE_CURRENT_LIST_DIR}/check_cad_exporter.py"
    --example-dir "${QC_WORK_DIR}/example-out" --example-stdout "${QC_WORK_DIR}/example-stdout.txt"
    --fit-dir "${QC_WORK_DIR}/cli-fit")
message("${check_stdout}")
