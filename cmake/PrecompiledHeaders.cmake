# Precompiled headers: most of a translation unit's compile time here is spent parsing the same
# third-party headers (OpenCL C++ bindings, nlohmann-json, fmt, GLM, OpenEXR, CLI11, GoogleTest).
# Each library and tool precompiles the ones it uses once; the test executables all reuse one
# precompiled set (tests/CMakeLists.txt). DECALCOMP_PCH=OFF builds without them (same program).
option(DECALCOMP_PCH "Precompile the third-party headers (shorter builds)" ON)

set(DECALCOMP_PCH_STD <algorithm> <array> <cmath> <cstdint> <filesystem> <fstream> <functional> <map>
                      <memory> <optional> <set> <string> <vector>)
set(DECALCOMP_PCH_GEOMETRY ${DECALCOMP_PCH_STD} <fmt/format.h> <glm/glm.hpp>)
set(DECALCOMP_PCH_CORE ${DECALCOMP_PCH_GEOMETRY} <CL/opencl.hpp> <nlohmann/json.hpp>)
set(DECALCOMP_PCH_IO ${DECALCOMP_PCH_CORE} <OpenEXR/ImfHeader.h> <OpenEXR/ImfChannelList.h>
                     <OpenEXR/ImfFrameBuffer.h>)

# decalcomp_precompile(TARGET HEADERS...): TARGET's sources see HEADERS precompiled.
function(decalcomp_precompile target)
  if(DECALCOMP_PCH)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()
