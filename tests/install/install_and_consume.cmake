# SPDX-License-Identifier: MIT
# cmake -DBUILD=... -DWORK=... -DCONSUMER=... -DVERSION=X.Y -DGENERATOR=... -DCXX=...
#       [-DPYTHON=python3 -DPYTHON_DIR=lib/python3/dist-packages] -P install_and_consume.cmake
# Installs BUILD into WORK/prefix, checks what was installed, then builds and
# runs the consumer project against it, and with PYTHON imports the Python
# package from PREFIX/PYTHON_DIR. Fails on the first thing wrong.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})
run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})

# Only the public headers are installed: the API and the header-only OMPL adapter over it.
file(GLOB_RECURSE headers RELATIVE ${prefix}/include ${prefix}/include/*)
list(SORT headers)
if(NOT headers STREQUAL "plancheck/ompl.h;plancheck/plancheck.h")
  message(FATAL_ERROR "installed headers: '${headers}', expected plancheck/ompl.h and plancheck/plancheck.h only")
endif()
file(GLOB libs ${prefix}/lib*/libplancheck.so)
if(NOT libs)
  message(FATAL_ERROR "no libplancheck.so under ${prefix}")
endif()
# The library exports the public API only: no internal plancheck:: name.
find_program(NM nm REQUIRED)
run(${NM} -DC --defined-only ${libs})
string(REGEX MATCHALL "[^\n]*plancheck::[^\n]*" api_symbols "${out}")
foreach(s IN LISTS api_symbols)
  string(REPLACE "plancheck::v0::" "" rest "${s}")
  if(rest MATCHES "plancheck::")
    message(FATAL_ERROR "libplancheck.so exports an internal name: ${s}")
  endif()
endforeach()
if(NOT out MATCHES "plancheck::v0::Checker::check")
  message(FATAL_ERROR "libplancheck.so does not export plancheck::Checker::check:\n${out}")
endif()

# A tiny scene: a bar 1 m over a slab, turning about y through (0, 0, 1).
set(scene ${WORK}/scene)
file(WRITE ${scene}/model.obj "o Slab
v -3 -1 -1\nv 3 -1 -1\nv -3 1 -1\nv 3 1 -1\nv -3 -1 0\nv 3 -1 0\nv -3 1 0\nv 3 1 0
f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6
o Bar
v 0 -0.1 0.875\nv 2 -0.1 0.875\nv 0 0.1 0.875\nv 2 0.1 0.875\nv 0 -0.1 1.125\nv 2 -0.1 1.125\nv 0 0.1 1.125\nv 2 0.1 1.125
f 9 11 10\nf 10 11 12\nf 13 14 15\nf 14 16 15\nf 9 10 13\nf 10 14 13\nf 11 15 12\nf 12 15 16\nf 9 13 11\nf 11 13 15\nf 10 12 14\nf 12 16 14
")
file(WRITE ${scene}/scene.json [[{"format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m", "angle_unit": "deg",
 "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1], "axis": [0, 1, 0], "limits": [-90, 30]}],
 "safety_margin": 0.05}]])

set(build ${WORK}/build)
run(${CMAKE_COMMAND} -S ${CONSUMER} -B ${build} -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DPLANCHECK_WANT=${VERSION})
run(${CMAKE_COMMAND} --build ${build})

# At 0 deg the bar's underside is 0.875 over the slab; at 45 deg its end is in it.
run(${build}/consumer ${scene}/scene.json 0)
if(NOT out STREQUAL "safe 0.875 Bar Slab\n")
  message(FATAL_ERROR "consumer at 0 deg printed '${out}', expected 'safe 0.875 Bar Slab'")
endif()
execute_process(COMMAND ${build}/consumer ${scene}/scene.json 45 RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 1 OR NOT out MATCHES "^collision 0 Bar Slab")
  message(FATAL_ERROR "consumer at 45 deg: status ${rc}, printed '${out}'")
endif()
execute_process(COMMAND ${build}/consumer ${scene}/missing.json RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "^plancheck: .*missing.json")
  message(FATAL_ERROR "consumer on a missing scene: status ${rc}, stderr '${err}'")
endif()

# The Python package under the prefix: imported from there (not the build
# folder), carrying its stubs, and giving the consumer's answers.
if(PYTHON)
  set(site ${prefix}/${PYTHON_DIR})
  foreach(f __init__.py _plancheck.pyi py.typed)
    if(NOT EXISTS ${site}/plancheck/${f})
      message(FATAL_ERROR "cmake --install did not install ${site}/plancheck/${f}")
    endif()
  endforeach()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c [=[
import pathlib, sys, plancheck
where = pathlib.Path(plancheck.__file__).resolve()
assert where.is_relative_to(pathlib.Path(sys.argv[1]).resolve()), where
r = plancheck.Scene(sys.argv[2], threads=1).check([[0], [45]])
print(r.verdict.tolist(), "%.12g" % r.min_distance[0], r.part_a_names[1], r.part_b_names[1])
]=] ${site} ${scene}/scene.json RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out STREQUAL "[0, 2] 0.875 Bar Slab\n")
    message(FATAL_ERROR "the installed Python package under ${site}: status ${rc}, printed '${out}'\n${err}")
  endif()
endif()

# find_package checks the version: the next minor version is refused (0.y).
string(REPLACE "." ";" v "${VERSION}")
list(GET v 0 major)
list(GET v 1 minor)
math(EXPR minor "${minor} + 1")
execute_process(COMMAND ${CMAKE_COMMAND} -S ${CONSUMER} -B ${WORK}/build-newer -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix} -DPLANCHECK_WANT=${major}.${minor}
  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "plancheck")
  message(FATAL_ERROR "find_package(plancheck ${major}.${minor}) accepted version ${VERSION}")
endif()
message(STATUS "installed, found, built and ran the consumer against ${prefix}")
