// The table of fuzz targets, by name.
#include "fuzz/fuzz_targets.hpp"

namespace decalcomp::fuzz {

const std::map<std::string, FuzzTarget>& fuzzTargets() {
    static const std::map<std::string, FuzzTarget> targets{
        {"camera", fuzzCamera}, {"cryptomatte", fuzzCryptomatte}, {"exr", fuzzExr},
        {"profile", fuzzProfile}, {"scene", fuzzScene},           {"texture", fuzzTexture},
    };
    return targets;
}

}  // namespace decalcomp::fuzz
