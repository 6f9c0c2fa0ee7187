#pragma once
// The "beauty" section of a renderer profile (docs/profiles.md "Beauty").
#include "decalcomp/beauty.hpp"
#include "decalcomp/json_fields.hpp"

namespace decalcomp {

// Throws Error(Input) naming the file and JSON path of a bad field.
BeautyModel parseBeautyModel(const JsonField& section);

}  // namespace decalcomp
