# The C++ package end to end (ctest: package_consumer): `cmake --install` of the build tree's C++
# component into WORK/prefix, the consumer project (tests/package/consumer) configured against it
# alone (CMAKE_PREFIX_PATH), built and run; any step that fails fails the test.
# docs/cpp.md's snippets are built and run with it (DOCS: that page; PYTHON: an interpreter for
# doc_snippets.py, which writes them as one program).
#   cmake -DBUILD=<flexure build> -DSOURCE=<consumer source> -DWORK=<scratch> -DGENERATOR=<gen>
#         -DDOCS=<docs/cpp.md> -DPYTHON=<python3> [-DLAUNCHER=<compiler launcher>]
#         -P build_consumer.cmake
foreach(variable BUILD SOURCE WORK GENERATOR DOCS PYTHON)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "build_consumer.cmake: -D${variable}=… is required")
  endif()
endforeach()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "build_consumer.cmake: ${what} failed (${status}): ${ARGN}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK})
run("the install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix --component cpp)
foreach(installed include/flexure/modeling/mesh.h include/flexure/optimize/problem.h
                  lib/cmake/flexure/flexureConfig.cmake lib/cmake/flexure/flexureConfigVersion.cmake)
  if(NOT EXISTS ${WORK}/prefix/${installed})
    message(FATAL_ERROR "build_consumer.cmake: the install has no ${installed}")
  endif()
endforeach()
set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
run("extracting docs/cpp.md's snippets" ${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/doc_snippets.py ${DOCS}
    ${WORK}/doc_snippets.cpp)
run("configuring the consumer" ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK}/prefix
    -DFLEXURE_DOC_SNIPPETS=${WORK}/doc_snippets.cpp ${launcher})
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK}/build)
run("the consumer" ${WORK}/build/consumer ${WORK})
file(MAKE_DIRECTORY ${WORK}/snippets)  # the snippets write patch.obj into their working folder
execute_process(COMMAND ${WORK}/build/doc_snippets WORKING_DIRECTORY ${WORK}/snippets
                RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "build_consumer.cmake: docs/cpp.md's snippets failed (${status})")
endif()
