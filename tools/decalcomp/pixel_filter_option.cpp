// --pixel-filter, shared by composite and batch (docs/pixel-filter.md).
#include "commands.hpp"
#include "decalcomp/error.hpp"
#include "decalcomp/pixel_filter.hpp"

namespace decalcomp::cli {

void addPixelFilterOption(CLI::App& command, std::optional<PixelFilter>& filter, bool& fast) {
    command
        .add_option_function<std::string>(
            "--pixel-filter",
            [&filter, &fast](const std::string& value) {
                fast = value == "auto:fast";
                if (value == "auto" || fast) {
                    filter.reset();
                    return;
                }
                try {
                    filter = parsePixelFilter(value, "--pixel-filter");
                } catch (const Error& e) {  // a bad option value: a usage error, as CLI11's own
                    throw CLI::ValidationError(e.what());
                }
            },
            "The renderer's pixel filter, which decals are integrated over: TYPE:WIDTH (box, gaussian, "
            "blackman-harris; Blender's default 1.5 px is blackman-harris:3), TYPE:WIDTH:fast (each decal once "
            "per pixel in closed form: about 4x faster, less exact where decals overlap), none (point-sampled), "
            "auto (a "
            "pixelFilter header, else none when the object-id pass holds whole numbers only, else the profile's), or "
            "auto:fast (that filter, evaluated fast)")
        ->default_str("auto");
}

}  // namespace decalcomp::cli
