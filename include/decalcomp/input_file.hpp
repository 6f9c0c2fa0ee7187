#pragma once
// The first check on every file a run reads: it exists, is a file, and can be opened.
#include <string>

namespace decalcomp {

// Throws Error(Input) "PATH: cannot open the WHAT: no such file" / "...: is a folder, not a
// file" / "...: permission denied" (`what`: "scene file", "texture", "EXR file"...).
void requireInputFile(const std::string& path, const std::string& what);

}  // namespace decalcomp
