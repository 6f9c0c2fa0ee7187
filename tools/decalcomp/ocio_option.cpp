// --ocio, shared by composite and batch (docs/colour.md).
#include "commands.hpp"

namespace decalcomp::cli {

void addOcioOption(CLI::App& command, std::string& ocio_config) {
    command.add_option("--ocio", ocio_config,
                       "OpenColorIO config for the scene's working_space and texture colorspace fields (default: "
                       "$OCIO)");
}

}  // namespace decalcomp::cli
