// --uv-origin, shared by composite and batch (docs/texture-space.md).
#include "commands.hpp"

namespace decalcomp::cli {

void addUvOriginOption(CLI::App& command, std::optional<bool>& uv_v_down) {
    command
        .add_option_function<std::string>(
            "--uv-origin",
            [&uv_v_down](const std::string& value) {
                if (value == "auto") uv_v_down.reset();
                else uv_v_down = value == "top";
            },
            "Where the UV pass's v = 0 lies, for texture-space decals: bottom (Blender, OBJ, most renderers), top, "
            "or auto (whichever puts more of the object's pixels on its rest mesh)")
        ->check(CLI::IsMember({"auto", "bottom", "top"}))
        ->default_str("auto");
}

}  // namespace decalcomp::cli
