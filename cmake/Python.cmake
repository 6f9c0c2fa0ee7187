# The Python module (docs/python.md): pybind11 from Debian (pybind11-dev) builds
# decalcomp/_decalcomp against the same position-independent layers as libdecalcomp, so the
# module is one self-contained extension. The package (python/decalcomp: __init__.py, stubs) is
# laid out beside it in <build>/python, which tests put on PYTHONPATH; `pip install .`
# (pyproject.toml, scikit-build-core) installs the same files.
# Debian's python3, whose numpy and pytest tools/install-deps.sh installs, even when another
# interpreter (pyenv, a venv) comes first on PATH; pip's builds bring their own interpreter.
if(NOT SKBUILD AND NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)
find_package(pybind11 CONFIG REQUIRED)

file(GLOB DECALCOMP_PYTHON_SOURCES CONFIGURE_DEPENDS src/python/*.cpp)
pybind11_add_module(decalcomp_python MODULE ${DECALCOMP_PYTHON_SOURCES})
set_target_properties(decalcomp_geometry decalcomp_core decalcomp_io PROPERTIES POSITION_INDEPENDENT_CODE ON)
target_link_libraries(decalcomp_python PRIVATE decalcomp_io decalcomp_warnings)
set(DECALCOMP_PYTHON_PACKAGE ${CMAKE_BINARY_DIR}/python/decalcomp)
set_target_properties(decalcomp_python PROPERTIES OUTPUT_NAME _decalcomp LIBRARY_OUTPUT_DIRECTORY ${DECALCOMP_PYTHON_PACKAGE})
decalcomp_precompile(decalcomp_python ${DECALCOMP_PCH_IO} <pybind11/pybind11.h> <pybind11/numpy.h> <pybind11/stl.h>
                     <pybind11/functional.h>)

file(GLOB DECALCOMP_PYTHON_FILES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/python/decalcomp/*)
set(DECALCOMP_PYTHON_COPIES)
foreach(file ${DECALCOMP_PYTHON_FILES})
  get_filename_component(name ${file} NAME)
  add_custom_command(OUTPUT ${DECALCOMP_PYTHON_PACKAGE}/${name}
    COMMAND ${CMAKE_COMMAND} -E copy ${file} ${DECALCOMP_PYTHON_PACKAGE}/${name} DEPENDS ${file} VERBATIM)
  list(APPEND DECALCOMP_PYTHON_COPIES ${DECALCOMP_PYTHON_PACKAGE}/${name})
endforeach()
add_custom_target(decalcomp_python_package ALL DEPENDS ${DECALCOMP_PYTHON_COPIES})
add_dependencies(decalcomp_python decalcomp_python_package)

# A wheel (scikit-build-core sets SKBUILD) holds the package at its root; a plain install puts it
# where Debian's python3 looks for a prefix's modules (/usr/local/lib/python3.11/dist-packages).
if(SKBUILD)
  set(DECALCOMP_PYTHON_DESTINATION decalcomp)
else()
  set(DECALCOMP_PYTHON_DESTINATION
      lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages/decalcomp)
endif()
install(TARGETS decalcomp_python decalcomp_images LIBRARY DESTINATION ${DECALCOMP_PYTHON_DESTINATION} COMPONENT python)
install(FILES ${DECALCOMP_PYTHON_FILES} DESTINATION ${DECALCOMP_PYTHON_DESTINATION} COMPONENT python)
