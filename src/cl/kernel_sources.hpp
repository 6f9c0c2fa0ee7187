#pragma once
// Kernel program assembly at run time (DECALCOMP_KERNEL_DIR), by the rules of
// cmake/AssembleKernels.cmake, which assembles the embedded copy at build time.
#include <string>

namespace decalcomp {

// Every *.cl in `dir` in name order, each `#include "NAME"` line (at the start of a line, NAME a
// file in `dir`) replaced by that file the first time the program meets it and by a comment after
// that, with `#line N "<line_prefix>FILE"` markers. Throws Error(Device) naming file and line for
// an include that is not there.
std::string assembleProgram(const std::string& dir, const std::string& line_prefix);

}  // namespace decalcomp
